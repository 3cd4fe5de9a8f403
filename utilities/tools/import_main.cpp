// roam-import DIR -o LOG [--heading-offset RAD] [--odometry-from-path FILE]
// A run in the CSV layout of ../shared/data/plaza1 (see utilities/dataset/csv_dataset.hpp) to an
// LCM log (see dataset_log.hpp). Prints a one-line summary; exit 2 with a one-line error.
#include <boost/program_options.hpp>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

#include "csv_dataset.hpp"
#include "dataset_log.hpp"

namespace po = boost::program_options;

int main(int argc, char** argv) {
  std::string dir, output;
  roam::CsvImportOptions options;
  po::options_description visible(
      "roam-import DIR -o LOG: a run in the CSV layout (odometry.csv, ranges.csv, groundtruth.csv,\n"
      "landmarks.csv) to an LCM log with INITIAL_POSE, BEACONS, GROUND_TRUTH, ODOMETRY, RANGE");
  visible.add_options()
      ("help,h", "this help")
      ("output,o", po::value(&output), "the LCM log to write (required)")
      ("heading-offset", po::value(&options.heading_offset_rad)->default_value(0.0),
       "RAD added to every ground-truth heading (e.g. 3.14159265 for reversed headings)")
      ("odometry-from-path", po::value(&options.odometry_from_path),
       "FILE: derive odometry from a dead-reckoned path CSV (time_s,x_m,y_m[,heading_rad]) "
       "instead of odometry.csv");
  po::options_description all;
  all.add(visible).add_options()("dir", po::value(&dir));
  po::positional_options_description positional;
  positional.add("dir", 1);
  try {
    po::variables_map vm;
    po::store(po::command_line_parser(argc, argv).options(all).positional(positional).run(), vm);
    if (vm.count("help")) {
      std::cout << visible << "\n";
      return 0;
    }
    po::notify(vm);
    if (dir.empty()) throw std::runtime_error("missing DIR (the folder with the CSV files)");
    if (output.empty()) throw std::runtime_error("missing -o LOG (the log to write)");
    const roam::Dataset dataset = roam::loadCsvDataset(dir, options);
    const roam::LogWriteSummary s = roam::writeDatasetLog(output, dataset);
    std::printf("roam-import: %s: %ld events (%ld odometry%s, %ld ranges, %ld ground truth, %ld beacons), "
                "%.3f s from utime %lld\n",
                output.c_str(), s.events, s.odometry,
                options.odometry_from_path.empty() ? "" : " from the path", s.ranges, s.ground_truth,
                s.beacons,
                dataset.ground_truth.empty()
                    ? 0.0
                    : 1e-6 * static_cast<double>(dataset.ground_truth.back().utime - dataset.start.utime),
                static_cast<long long>(dataset.start.utime));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "roam-import: error: %s\n", e.what());
    return 2;
  }
}
