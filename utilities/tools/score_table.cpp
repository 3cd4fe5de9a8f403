#include "score_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace roam {
namespace {

std::string fixed(double value, int decimals) {
  if (!std::isfinite(value)) return "-";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

std::string exact(double value) {  // CSV / JSON: every digit, empty when unknown
  if (!std::isfinite(value)) return "";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

std::string jsonNumber(double value) {
  const std::string text = exact(value);
  return text.empty() ? "null" : text;
}

std::string jsonString(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += std::string("\\") + c;
    else if (static_cast<unsigned char>(c) < 0x20) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
      out += buffer;
    } else out += c;
  }
  return out + "\"";
}

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += (c == '"') ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

const EstimatorScore* findEstimator(const RunScores& run, const std::string& name) {
  for (const auto& e : run.estimators) {
    if (e.estimator == name) return &e;
  }
  return nullptr;
}

// Estimator names over all runs, in order of first appearance.
std::vector<std::string> estimatorNames(const std::vector<RunScores>& runs) {
  std::vector<std::string> names;
  for (const auto& run : runs) {
    for (const auto& e : run.estimators) {
      if (std::find(names.begin(), names.end(), e.estimator) == names.end()) names.push_back(e.estimator);
    }
  }
  return names;
}

using Table = std::vector<std::vector<std::string>>;  // row 0 = header

Table buildTable(const std::vector<RunScores>& runs, TableMetric metric) {
  const bool mean = metric != TableMetric::kRmse, rmse = metric != TableMetric::kMean;
  const bool both = mean && rmse;
  Table table;
  std::vector<std::string> header{"estimator", "segment"};
  for (const auto& run : runs) {
    if (mean) header.push_back(run.run + " mean (m)");
    if (rmse) header.push_back(run.run + " RMSE (m)");
  }
  table.push_back(header);
  const int per_run = both ? 2 : 1;
  struct Segment {
    const char* label;
    const ErrorStats PathScore::*stats;
  };
  const Segment segments[] = {{"full path", &PathScore::full},
                              {"last 10 %", &PathScore::last10},
                              {"best 10 %", &PathScore::best10},
                              {"worst 10 %", &PathScore::worst10}};
  for (const std::string& name : estimatorNames(runs)) {
    bool first = true;
    for (const Segment& segment : segments) {
      std::vector<std::string> row{first ? name : "", segment.label};
      first = false;
      for (const auto& run : runs) {
        const EstimatorScore* e = findEstimator(run, name);
        const ErrorStats* stats = e ? &(e->score.*segment.stats) : nullptr;
        auto cell = [&](double value) {
          const std::string text = fixed(value, 2);
          return e->ranked() || text == "-" ? text : "(" + text + ")";
        };
        if (mean) row.push_back(stats ? cell(stats->mean_m) : "-");
        if (rmse) row.push_back(stats ? cell(stats->rmse_m) : "-");
      }
      table.push_back(row);
    }
    auto single = [&](const char* label, auto value_of) {
      std::vector<std::string> row{"", label};
      for (const auto& run : runs) {
        const EstimatorScore* e = findEstimator(run, name);
        row.push_back(e ? value_of(*e) : "-");
        for (int i = 1; i < per_run; ++i) row.push_back("");
      }
      table.push_back(row);
    };
    single("max", [](const EstimatorScore& e) { return fixed(e.score.max_m, 2); });
    single("beacons", [](const EstimatorScore& e) { return fixed(e.score.beacon_error_m, 2); });
    single("CPU (s)", [](const EstimatorScore& e) { return e.cpu_s ? fixed(*e.cpu_s, 3) : "-"; });
    single("coverage", [](const EstimatorScore& e) {
      return fixed(100.0 * e.coverage, 0) + " %" + (e.ranked() ? "" : " (partial)");
    });
  }
  return table;
}

// A team run: one row per estimator (see score_table.hpp).
Table buildTeamTable(const RunScores& run, TableMetric metric) {
  const bool mean = metric != TableMetric::kRmse, rmse = metric != TableMetric::kMean;
  Table table;
  std::vector<std::string> header{"estimator"};
  if (mean) header.push_back("team mean (m)");
  if (rmse) header.push_back("team RMSE (m)");
  if (mean) header.push_back("team aligned mean (m)");
  if (rmse) header.push_back("team aligned RMSE (m)");
  for (const std::string& robot : run.robots)
    header.push_back(robot + (run.aligned ? " aligned" : "") + (mean ? " mean (m)" : " RMSE (m)"));
  for (const char* label : {"beacons", "CPU (s)", "coverage"}) header.push_back(label);
  table.push_back(header);
  for (const EstimatorScore& e : run.estimators) {
    if (!e.team) continue;
    const TeamScore& team = *e.team;
    auto cell = [](double value, bool ranked) {
      const std::string text = fixed(value, 2);
      return ranked || text == "-" ? text : "(" + text + ")";
    };
    std::vector<std::string> row{e.estimator};
    for (const ErrorStats* stats : {&team.unaligned, &team.aligned}) {
      if (mean) row.push_back(cell(stats->mean_m, e.ranked()));
      if (rmse) row.push_back(cell(stats->rmse_m, e.ranked()));
    }
    for (const RobotScore& robot : team.robots) {
      if (!robot.published()) row.push_back("no path");
      else row.push_back(cell(mean ? robot.score.full.mean_m : robot.score.full.rmse_m,
                              robot.coverage() >= kMinRankedCoverage));
    }
    row.push_back(fixed(run.aligned ? team.aligned_beacon_error_m : team.beacon_error_m, 2));
    row.push_back(e.cpu_s ? fixed(*e.cpu_s, 3) : "-");
    row.push_back(fixed(100.0 * e.coverage, 0) + " %" + (e.ranked() ? "" : " (partial)"));
    table.push_back(row);
  }
  return table;
}

std::string teamTitle(const RunScores& run) {
  std::string names;
  for (const std::string& robot : run.robots) names += (names.empty() ? "" : ", ") + robot;
  return run.run + ": team of " + std::to_string(run.robots.size()) + " robot" + (run.robots.size() == 1 ? "" : "s") +
         " (" + names + "); team aligned = one rigid fit of all robots' paths together\n";
}

// name_columns: left-aligned leading columns; rules: a rule before each estimator (a row with a
// first cell), else one under the header.
std::string renderText(const Table& table, size_t name_columns = 2, bool rules = true) {
  std::vector<size_t> width(table[0].size(), 0);
  for (const auto& row : table)
    for (size_t i = 0; i < row.size(); ++i) width[i] = std::max(width[i], row[i].size());
  std::ostringstream out;
  for (size_t r = 0; r < table.size(); ++r) {
    const auto& row = table[r];
    if (rules ? (r > 0 && !row[0].empty()) : r == 1) {  // a rule before each estimator
      size_t total = 0;
      for (size_t w : width) total += w + 2;
      out << std::string(total - 2, '-') << "\n";
    }
    std::string line;
    for (size_t i = 0; i < row.size(); ++i) {
      const std::string& cell = row[i];
      const std::string pad(width[i] - cell.size(), ' ');
      line += (i < name_columns ? cell + pad : pad + cell);  // names left, numbers right
      if (i + 1 < row.size()) line += "  ";
    }
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out << line << "\n";
  }
  return out.str();
}

std::string renderMarkdown(const Table& table, size_t name_columns = 2) {
  std::ostringstream out;
  for (size_t r = 0; r < table.size(); ++r) {
    out << "|";
    for (const auto& cell : table[r]) out << " " << cell << " |";
    out << "\n";
    if (r == 0) {
      out << "|";
      for (size_t i = 0; i < table[0].size(); ++i) out << (i < name_columns ? "---|" : "---:|");
      out << "\n";
    }
  }
  return out.str();
}

// ",matched,full_mean_m,...,worst10_rmse_m,max_m" of one path's figures.
std::string csvPathCells(const PathScore& s) {
  std::string out = "," + std::to_string(s.matched);
  for (const ErrorStats* stats : {&s.full, &s.last10, &s.best10, &s.worst10})
    out += "," + exact(stats->mean_m) + "," + exact(stats->rmse_m);
  return out + "," + exact(s.max_m);
}

std::string renderCsv(const std::vector<RunScores>& runs) {
  const bool any_team = std::any_of(runs.begin(), runs.end(), [](const RunScores& r) { return r.isTeam(); });
  std::ostringstream out;
  out << "run,estimator,scored,matched,full_mean_m,full_rmse_m,last10_mean_m,last10_rmse_m,"
         "best10_mean_m,best10_rmse_m,worst10_mean_m,worst10_rmse_m,max_m,beacon_error_m,cpu_s,state,"
         "coverage,ranked"
      << (any_team ? ",robot,team_aligned_mean_m,team_aligned_rmse_m" : "") << "\n";
  const char* no_team_cells = any_team ? ",,," : "";
  for (const auto& run : runs) {
    for (const auto& e : run.estimators) {
      const std::string cpu = e.cpu_s ? exact(*e.cpu_s) : "";
      if (!e.team) {
        const PathScore& s = e.score;
        out << csvField(run.run) << "," << csvField(e.estimator) << "," << e.scored << csvPathCells(s) << ","
            << exact(s.beacon_error_m) << "," << cpu << "," << csvField(e.state) << "," << exact(e.coverage) << ","
            << (e.ranked() ? "true" : "false") << no_team_cells << "\n";
        continue;
      }
      const TeamScore& team = *e.team;
      out << csvField(run.run) << "," << csvField(e.estimator) << ",team," << team.matched << ","
          << exact(team.unaligned.mean_m) << "," << exact(team.unaligned.rmse_m) << ",,,,,,,"
          << exact(team.unaligned_max_m) << "," << exact(team.beacon_error_m) << "," << cpu << ","
          << csvField(e.state) << "," << exact(e.coverage) << "," << (e.ranked() ? "true" : "false")
          << ",team," << exact(team.aligned.mean_m) << "," << exact(team.aligned.rmse_m) << "\n";
      for (const RobotScore& robot : team.robots) {
        out << csvField(run.run) << "," << csvField(e.estimator) << ","
            << (robot.published() ? robot.scored : "none") << csvPathCells(robot.score) << ",,,,"
            << exact(robot.coverage()) << "," << (robot.coverage() >= kMinRankedCoverage ? "true" : "false") << ","
            << csvField(robot.robot) << ",,\n";
      }
    }
  }
  return out.str();
}

std::string jsonStats(const ErrorStats& s) {
  return "{\"mean_m\": " + jsonNumber(s.mean_m) + ", \"rmse_m\": " + jsonNumber(s.rmse_m) +
         ", \"count\": " + std::to_string(s.count) + "}";
}

// "\"matched\": ..., \"full\": ..., ..., \"max_m\": ..." of one path's figures.
std::string jsonPathFields(const PathScore& s) {
  return "\"matched\": " + std::to_string(s.matched) + ", \"full\": " + jsonStats(s.full) +
         ", \"last10\": " + jsonStats(s.last10) + ", \"best10\": " + jsonStats(s.best10) +
         ", \"worst10\": " + jsonStats(s.worst10) + ", \"max_m\": " + jsonNumber(s.max_m);
}

std::string jsonTeam(const EstimatorScore& e) {
  const TeamScore& team = *e.team;
  std::ostringstream out;
  out << "{\"estimator\": " << jsonString(e.estimator) << ", \"team\": {\"matched\": " << team.matched
      << ", \"unaligned\": " << jsonStats(team.unaligned) << ", \"aligned\": " << jsonStats(team.aligned)
      << ", \"max_m\": " << jsonNumber(team.unaligned_max_m) << ", \"aligned_max_m\": " << jsonNumber(team.aligned_max_m)
      << ", \"beacon_error_m\": " << jsonNumber(team.beacon_error_m)
      << ", \"aligned_beacon_error_m\": " << jsonNumber(team.aligned_beacon_error_m) << "}"
      << ", \"cpu_s\": " << (e.cpu_s ? jsonNumber(*e.cpu_s) : "null") << ", \"state\": " << jsonString(e.state)
      << ", \"coverage\": " << jsonNumber(e.coverage) << ", \"ranked\": " << (e.ranked() ? "true" : "false")
      << ", \"robots\": {";
  for (size_t i = 0; i < team.robots.size(); ++i) {
    const RobotScore& robot = team.robots[i];
    out << (i ? ", " : "") << jsonString(robot.robot) << ": {\"scored\": "
        << (robot.published() ? jsonString(robot.scored) : "null") << ", " << jsonPathFields(robot.score)
        << ", \"coverage\": " << jsonNumber(robot.coverage())
        << ", \"ranked\": " << (robot.coverage() >= kMinRankedCoverage ? "true" : "false") << "}";
  }
  out << "}}";
  return out.str();
}

std::string renderJson(const std::vector<RunScores>& runs) {
  std::ostringstream out;
  out << "{\"runs\": [";
  for (size_t r = 0; r < runs.size(); ++r) {
    const RunScores& run = runs[r];
    out << (r ? ",\n" : "\n") << "  {\"run\": " << jsonString(run.run) << ", \"log\": " << jsonString(run.log)
        << ", \"events\": " << run.events << ", \"skipped_events\": " << run.skipped
        << ", \"ground_truth\": " << run.ground_truth;
    if (run.isTeam()) {
      out << ", \"robots\": [";
      for (size_t i = 0; i < run.robots.size(); ++i) out << (i ? ", " : "") << jsonString(run.robots[i]);
      out << "]";
    }
    out << ", \"estimators\": [";
    for (size_t i = 0; i < run.estimators.size(); ++i) {
      const EstimatorScore& e = run.estimators[i];
      const PathScore& s = e.score;
      out << (i ? ",\n" : "\n") << "    ";
      if (e.team) {
        out << jsonTeam(e);
        continue;
      }
      out << "{\"estimator\": " << jsonString(e.estimator) << ", \"scored\": " << jsonString(e.scored) << ", "
          << jsonPathFields(s) << ", \"beacon_error_m\": " << jsonNumber(s.beacon_error_m)
          << ", \"cpu_s\": " << (e.cpu_s ? jsonNumber(*e.cpu_s) : "null")
          << ", \"state\": " << jsonString(e.state) << ", \"coverage\": " << jsonNumber(e.coverage)
          << ", \"ranked\": " << (e.ranked() ? "true" : "false") << "}";
    }
    out << "\n  ]}";
  }
  out << "\n]}\n";
  return out.str();
}

double coverageOf(const PathScore& score, const ResultLog& log) {
  return log.ground_truth.empty() ? 0.0
                                  : static_cast<double>(score.matched) / static_cast<double>(log.ground_truth.size());
}

}  // namespace

RunScores scoreRun(const ResultLog& log, const std::string& run, bool aligned, bool with_odometry) {
  RunScores scores;
  scores.run = run;
  scores.log = log.path;
  scores.events = log.events;
  scores.skipped = log.skipped;
  scores.ground_truth = log.ground_truth.size();
  scores.aligned = aligned;
  if (log.isTeam()) {  // no dead reckoning of its own: only what the log holds as an estimator
    scores.robots = log.robotNames();
    scores.ground_truth = 0;
    for (const auto& [robot, truth] : log.team_ground_truth) scores.ground_truth += truth.size();
    for (const EstimatorOutputs& out : log.estimators) {
      EstimatorScore e;
      e.estimator = out.name;
      e.scored = "team";
      e.team = scoreTeam(out, log.team_ground_truth, aligned, log.beacons);
      e.coverage = e.team->coverage();
      e.cpu_s = out.cpu_total_s;
      e.state = out.state;
      scores.estimators.push_back(e);
    }
    return scores;
  }
  if (with_odometry && log.start && !log.odometry.empty()) {
    EstimatorScore e;
    e.estimator = kOdometryRowName;
    e.scored = "odometry";
    e.score = scorePath(integrateOdometry(*log.start, log.odometry), log.ground_truth, aligned);
    e.coverage = coverageOf(e.score, log);
    scores.estimators.push_back(e);
  }
  for (const EstimatorOutputs& out : log.estimators) {
    EstimatorScore e;
    e.estimator = out.name;
    e.scored = out.trajectory ? "trajectory" : "poses";
    e.score = scorePath(out.scoredPath(), log.ground_truth, aligned, out.map, log.beacons);
    e.coverage = coverageOf(e.score, log);
    e.cpu_s = out.cpu_total_s;
    e.state = out.state;
    scores.estimators.push_back(e);
  }
  return scores;
}

std::string formatScores(const std::vector<RunScores>& runs, TableFormat format, TableMetric metric) {
  switch (format) {
    case TableFormat::kText:
    case TableFormat::kMarkdown: {
      const bool text = format == TableFormat::kText;
      std::vector<RunScores> single;
      for (const auto& run : runs) {
        if (!run.isTeam()) single.push_back(run);
      }
      std::string out;
      if (!single.empty()) out = text ? renderText(buildTable(single, metric)) : renderMarkdown(buildTable(single, metric));
      for (const auto& run : runs) {
        if (!run.isTeam()) continue;
        if (!out.empty()) out += "\n";
        const Table table = buildTeamTable(run, metric);
        out += teamTitle(run) + (text ? "" : "\n") + (text ? renderText(table, 1, false) : renderMarkdown(table, 1));
      }
      return out;
    }
    case TableFormat::kCsv: return renderCsv(runs);
    case TableFormat::kJson: return renderJson(runs);
  }
  return "";
}

}  // namespace roam
