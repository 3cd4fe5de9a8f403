// roam-run: loads the estimator plugins named in an INI config and runs them over a log
// (deterministic replay, as fast as the CPU allows) or a live LCM bus.
//
//   roam-run CONFIG [--set section.key=value]... [--input LOG|URL] [--output LOG]
//                   [--print-config] [--duration S] [--no-progress] [--verbose]
//
// Exit status: 0 all estimators finished; 1 an estimator failed (named on stderr);
// 2 bad config, missing plugin, unreadable input (before any data is read); 3 the output log
// could not be written (full disk, removed, cannot grow): the run stopped there.
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <boost/program_options.hpp>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "config.hpp"
#include "host.hpp"
#include "isolated_instance.hpp"
#include "live.hpp"
#include "log_sink.hpp"
#include "plugin_library.hpp"
#include "rejection_warning.hpp"
#include "run_notes.hpp"
#include "replay.hpp"
#include "threaded_instance.hpp"
#include "roam/messages.hpp"

namespace po = boost::program_options;
namespace fs = std::filesystem;
using namespace roam::runtime;

namespace {

std::atomic<bool> g_stop{false};
std::atomic<int> g_signals{0};

void onSignal(int) {
  g_stop.store(true);
  if (g_signals.fetch_add(1) >= 1) {
    // Second signal: leave at once. Every event already written is complete on disk
    // (the output log is flushed after each batch), so the log stays readable.
    _exit(130);
  }
}

std::string defaultPluginPath() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "lib/roam/plugins";
  return (exe.parent_path().parent_path() / "lib" / "roam" / "plugins").lexically_normal().string();
}

int startupError(const std::string& message) {
  std::fprintf(stderr, "roam-run: error: %s\n", message.c_str());
  return 2;
}

// The output log failed mid-run (full disk, removed, cannot grow): one line, exit 3.
int outputError(const LogSink& log) {
  std::fprintf(stderr, "roam-run: error: %s\n", log.error().c_str());
  return 3;
}

}  // namespace

int main(int argc, char** argv) {
  po::options_description options("roam-run CONFIG [options]");
  std::vector<std::string> overrides;
  std::string config_path, input_override, output_override;
  double duration_s = 0.0;
  options.add_options()
      ("help,h", "show this help")
      ("config", po::value(&config_path), "the INI config file")
      ("set", po::value(&overrides)->composing(), "override a config value: section.key=value (repeatable)")
      ("input", po::value(&input_override), "override [runtime] input: a log file or an LCM URL")
      ("output", po::value(&output_override), "override [runtime] output (\"\" for none)")
      ("print-config", "print the effective config (defaults included) and exit")
      ("duration", po::value(&duration_s), "live mode: stop after this many seconds")
      ("no-progress", "no progress bar")
      ("verbose,v", "more detail on stderr");
  po::positional_options_description positional;
  positional.add("config", 1);
  po::variables_map args;
  try {
    po::store(po::command_line_parser(argc, argv).options(options).positional(positional).run(), args);
    po::notify(args);
  } catch (const po::error& error) {
    return startupError(std::string(error.what()) + " (see roam-run --help)");
  }
  if (args.count("help") || config_path.empty()) {
    std::cout << options << "\n";
    return args.count("help") ? 0 : 2;
  }

  RunConfig config;
  try {
    if (args.count("input")) overrides.push_back("runtime.input=" + fs::absolute(input_override).string());
    config = loadConfig(config_path, overrides, defaultPluginPath());
    if (args.count("input") && input_override.find("://") != std::string::npos) config.input = input_override;
    if (args.count("output")) config.output = output_override.empty() ? "" : fs::absolute(output_override).string();
  } catch (const ConfigError& error) {
    return startupError(error.what());
  }

  // Load every plugin and create every instance before reading any data.
  std::vector<EstimatorSlot> slots;
  std::vector<roam::KeyValues> effective;
  std::vector<EstimatorSection> expanded;  // the sections as run (a team's one-robot copies)
  for (const auto& section : config.estimators) {
    try {
      auto library = PluginLibrary::open(config.plugin_path, section.plugin);
      roam::KeyValues values;
      for (const auto& setting : section.plugin_settings) values.emplace_back(setting.key, setting.value);
      // A team run gives a one-robot plugin an instance per robot, NAME_<robot>, fed that robot's
      // inputs alone; a team plugin one instance, told the team.
      const std::vector<EstimatorSection> runs = teamRuns(config, section, library->estimatesTeams());
      for (const EstimatorSection& run : runs) {
        EstimatorSlot slot;
        slot.section = run;
        const CallLimits limits{run.max_update_s, run.max_finish_s};
        if (run.isolated) {
          slot.instance = std::make_unique<IsolatedInstance>(library, run.name, values,
                                                             IsolationLimits{limits, run.max_memory_mb});
        } else {
          slot.instance = std::make_unique<PluginInstance>(library, run.name, values, limits);
        }
        if (config.isTeam() && run.robot < 0 && !slot.instance->setTeam(config.team)) {
          throw PluginError(slot.instance->error());
        }
        effective.push_back(slot.instance->effectiveConfig());
        slots.push_back(std::move(slot));
        expanded.push_back(run);
      }
    } catch (const PluginConfigError& error) {
      const Origin origin = error.key().empty() ? section.section_origin : section.originOf(error.key());
      std::string where = origin.describe() + " [estimator." + section.name + "]";
      if (!error.key().empty()) where += " " + error.key();
      return startupError(where + ": " + error.what());
    } catch (const PluginError& error) {
      return startupError(section.plugin_origin.describe() + " [estimator." + section.name +
                          "] plugin: " + error.what());
    }
  }
  // threads > 1: in-process estimators go to workers, round robin (isolated ones already run in
  // processes of their own). One estimator needs no worker. The pool starts after every isolated
  // child is forked: fork copies only the calling thread.
  std::unique_ptr<WorkerPool> pool;
  const int in_process = static_cast<int>(std::count_if(slots.begin(), slots.end(),
                                                        [](const EstimatorSlot& slot) { return !slot.section.isolated; }));
  if (config.threads > 1 && in_process > 1 && !args.count("print-config")) {
    pool = std::make_unique<WorkerPool>(std::min(config.threads, in_process));
    int next = 0;
    for (auto& slot : slots) {
      if (slot.section.isolated) continue;
      slot.instance = std::make_unique<ThreadedInstance>(std::move(slot.instance), pool.get(), next++);
    }
  }
  config.estimators = expanded;
  if (args.count("print-config")) {
    std::cout << formatConfig(config, effective);
    return 0;
  }

  if (!config.isLive()) {
    try {
      checkInputLog(config.input);
    } catch (const std::exception& error) {
      return startupError(error.what());
    }
  }
  if (args.count("input") && !args.count("output") && !config.output.empty() && fs::exists(config.output)) {
    std::fprintf(stderr,
                 "roam-run: note: --input without --output: the results replace %s, the config's output "
                 "(--output FILE writes elsewhere, --output \"\" nowhere)\n",
                 config.output.c_str());
  }

  std::unique_ptr<LogSink> log_sink;
  try {
    if (!config.output.empty()) log_sink = std::make_unique<LogSink>(config.output);
  } catch (const std::exception& error) {
    return startupError(error.what());
  }

  if (log_sink) log_sink->stopOnFailure(&g_stop);
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  std::signal(SIGXFSZ, SIG_IGN);  // a file that may not grow: write(2) says EFBIG, the log sink reports it
  const bool progress = !args.count("no-progress") && isatty(STDERR_FILENO);

  int status = 0;
  std::unique_ptr<Host> host;
  if (config.isLive()) {
    LiveOptions live;
    live.duration_s = duration_s;
    live.verbose = args.count("verbose") > 0;
    try {
      status = runLive(config, std::move(slots), log_sink.get(), live, g_stop, &host);
    } catch (const std::exception& error) {
      return startupError(error.what());
    }
    if (status != 0) return status;
    if (log_sink && log_sink->failed()) return outputError(*log_sink);
  } else {
    NullSink null_sink;
    Sink* sink = log_sink ? static_cast<Sink*>(log_sink.get()) : &null_sink;
    host = std::make_unique<Host>(config, std::move(slots), sink, log_sink.get());
    ReplayReport report;
    try {
      report = replayLog(config.input, *host, g_stop, progress);
    } catch (const std::exception& error) {
      return startupError(error.what());
    }
    if (log_sink && log_sink->failed()) return outputError(*log_sink);
    host->finish();
    if (!report.damage().empty()) {
      std::fprintf(stderr, "roam-run: warning: %s: %s\n", config.input.c_str(), report.damage().c_str());
    }
    if (report.interrupted) std::fprintf(stderr, "roam-run: interrupted: finished with the data so far\n");
  }
  if (log_sink) log_sink->flush();
  if (log_sink && log_sink->failed()) return outputError(*log_sink);
  for (const auto& line : host->summary()) std::fprintf(stderr, "%s\n", line.c_str());
  if (const std::string late = host->lateInputWarning(); !late.empty()) std::fprintf(stderr, "roam-run: %s\n", late.c_str());
  for (size_t i = 0; i < host->estimators().size() && i < effective.size(); ++i) {
    const auto& slot = host->estimators()[i];
    const auto status = slot.instance->status();
    for (const auto& line : rejectionWarnings(slot.section.name, status, effective[i]))
      std::fprintf(stderr, "roam-run: %s\n", line.c_str());
    for (const auto& line : runNotes(slot.section.name, status, effective[i]))
      std::fprintf(stderr, "roam-run: %s\n", line.c_str());
  }
  // Which estimators had no range to work with: of one robot, the ranges on its channel; of a
  // team, every range (to beacons and between robots).
  const auto& counters = host->counters();
  for (int robot = config.isTeam() ? -1 : 0; robot < static_cast<int>(std::max<size_t>(1, config.team.size())); ++robot) {
    std::vector<EstimatorRangeUse> range_use;
    for (const auto& slot : host->estimators())
      if (!slot.instance->failed() && (!config.isTeam() || slot.section.robot == robot))
        range_use.push_back({slot.section.name, slot.instance->status()});
    int64_t ranges = counters.ranges;
    std::string channel = config.range_channel;
    if (config.isTeam() && robot < 0) {
      ranges += counters.robot_ranges;
      channel += "_<robot> or " + std::string(roam::channels::ROBOT_RANGE) + "_<robot>";
    } else if (config.isTeam()) {
      const auto it = counters.ranges_by_robot.find(robot);
      ranges = it == counters.ranges_by_robot.end() ? 0 : it->second;
      channel += "_" + config.team[static_cast<size_t>(robot)];
    }
    for (const auto& line : rangeUseNotes(ranges, channel, range_use)) std::fprintf(stderr, "roam-run: %s\n", line.c_str());
  }
  // A team's ranges between robots reach team plugins only: say which estimators ran each robot
  // alone without them.
  if (config.isTeam() && counters.robot_ranges > 0) {
    std::string alone;
    for (const auto& section : config.estimators) {  // as run: one-robot plugins' copies end in _<robot>
      if (section.robot != 0) continue;
      const std::string base = section.name.substr(0, section.name.size() - config.team[0].size() - 1);
      alone += (alone.empty() ? "" : ", ") + base;
    }
    if (!alone.empty())
      std::fprintf(stderr,
                   "roam-run: note: ran each robot alone, without the %lld ranges between robots (their plugins "
                   "estimate one robot; spectral_batch and ekf solve the team): %s\n",
                   static_cast<long long>(counters.robot_ranges), alone.c_str());
  }
  std::vector<std::string> failures;
  for (const auto& slot : host->estimators()) {
    if (slot.instance->failed()) {
      failures.push_back("roam-run: estimator '" + slot.section.name + "' failed: " + slot.instance->error());
    }
  }
  const bool any_isolated = std::any_of(config.estimators.begin(), config.estimators.end(),
                                        [](const EstimatorSection& section) { return section.isolated; });
  host.reset();  // ends the isolated estimators' processes, so their peak memory can be read
  pool.reset();
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) == 0) {  // every in-process estimator and the runtime together
    std::fprintf(stderr, "peak memory: %.1f MB resident\n", static_cast<double>(usage.ru_maxrss) / 1024.0);
  }
  if (any_isolated && getrusage(RUSAGE_CHILDREN, &usage) == 0) {
    std::fprintf(stderr, "peak memory of the largest isolated estimator's process: %.1f MB resident\n",
                 static_cast<double>(usage.ru_maxrss) / 1024.0);
  }
  if (!config.output.empty()) std::fprintf(stderr, "output: %s\n", config.output.c_str());
  for (const auto& failure : failures) std::fprintf(stderr, "%s\n", failure.c_str());
  if (!failures.empty()) status = 1;
  return status;
}
