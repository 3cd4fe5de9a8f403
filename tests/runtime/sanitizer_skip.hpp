// Tests of faults that the sanitizers change on purpose skip themselves in the ASan + UBSan
// build and run in the Release pass (utilities/test runs both):
//  - a deliberate null-pointer store is reported by UBSan (exit 1) before it can raise SIGSEGV;
//  - ASan reserves terabytes of shadow address space and reports its own out-of-memory error, so
//    an RLIMIT_AS limit does not end in std::bad_alloc;
//  - roam-run's live mode subscribes through LCM 1.3.1's C++ templates, which trip UBSan's vptr
//    check inside LCM's own header (the reason the live suites run in the Release pass only).
#pragma once

#include <gtest/gtest.h>

#ifdef ROAM_SANITIZED
#define ROAM_SKIP_UNDER_SANITIZERS(why) GTEST_SKIP() << "changed by the sanitizers: " << why
#else
#define ROAM_SKIP_UNDER_SANITIZERS(why) (void)0
#endif
