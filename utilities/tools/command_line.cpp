#include "command_line.hpp"

#include <iostream>

namespace po = boost::program_options;

namespace roam {
namespace tools {

bool parseCommandLine(int argc, char** argv, const po::options_description& visible,
                      const po::options_description& hidden, const po::positional_options_description& positional,
                      po::variables_map* vm) {
  po::options_description all;
  all.add(visible).add(hidden);
  po::store(po::command_line_parser(argc, argv).options(all).positional(positional).run(), *vm);
  if (vm->count("help")) {
    std::cout << visible << "\n";
    return false;
  }
  po::notify(*vm);
  return true;
}

bool parseCommandLine(int argc, char** argv, const po::options_description& visible, po::variables_map* vm) {
  return parseCommandLine(argc, argv, visible, po::options_description(), po::positional_options_description(), vm);
}

}  // namespace tools
}  // namespace roam
