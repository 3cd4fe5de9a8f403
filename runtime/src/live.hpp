// Live mode: roam-run on an LCM bus. Subscribes to the input channels, feeds the estimators
// as messages arrive (using the messages' utime, never the receive time), publishes their
// outputs on the bus and, optionally, writes inputs and outputs to a log. Ends on SIGINT/SIGTERM
// or after --duration; each estimator's finish step then runs and the log is closed.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "config.hpp"
#include "host.hpp"
#include "log_sink.hpp"

namespace roam {
namespace runtime {

struct LiveOptions {
  double duration_s = 0.0;  // 0: until a signal
  bool verbose = false;
};

// The URL roam-run opens for a live input: a udpm:// URL without recv_buf_size gets
// recv_buf_size=4194304 (4 MB, which the kernel caps at net.core.rmem_max). A UDP multicast
// socket receives every datagram on its port, roam-run's own outputs included: a final
// TRAJECTORY of Plaza 1 is ~200 datagrams in one burst, and the kernel's default 208 KB buffer
// can overflow behind it whenever roam-run is slow to read. (The 49 of 13186 inputs once lost on
// a loaded two-core host were probably lost in LCM's queue, kInputQueueCapacity below, not in
// the socket.) Other URLs are returned unchanged.
std::string liveBusUrl(const std::string& url);

// How many received messages LCM may hold per input channel while roam-run is busy. LCM's
// default is 30, and past it LCM drops the message without a word: at 20x Plaza 1 that is 0.3 s
// of odometry, so any longer pause of the process lost odometry and ranges (CI's live tests
// showed stalls of 0.34-0.82 s, cause unknown). 100000 is 100 s of 1 kHz odometry (a few tens
// of MB); a backlog that long is reported long before (the live backlog warning, at 1 s).
constexpr int kInputQueueCapacity = 100000;

// Returns 0, or 2 if the bus cannot be opened (nothing has run then). `host` receives the
// host so the caller can print the summary.
int runLive(const RunConfig& config, std::vector<EstimatorSlot> slots, LogSink* log,
            const LiveOptions& options, const std::atomic<bool>& stop, std::unique_ptr<Host>* host);

}  // namespace runtime
}  // namespace roam
