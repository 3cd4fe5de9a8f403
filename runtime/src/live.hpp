// Live mode: roam-run on an LCM bus. Subscribes to the input channels, feeds the estimators
// as messages arrive (using the messages' utime, never the receive time), publishes their
// outputs on the bus and, optionally, writes inputs and outputs to a log. Ends on SIGINT/SIGTERM
// or after --duration; each estimator's finish step then runs and the log is closed.
#pragma once

#include <atomic>
#include <memory>
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

// Returns 0, or 2 if the bus cannot be opened (nothing has run then). `host` receives the
// host so the caller can print the summary.
int runLive(const RunConfig& config, std::vector<EstimatorSlot> slots, LogSink* log,
            const LiveOptions& options, const std::atomic<bool>& stop, std::unique_ptr<Host>* host);

}  // namespace runtime
}  // namespace roam
