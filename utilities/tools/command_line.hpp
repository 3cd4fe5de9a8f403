// The command line every roam tool parses the same way (Boost.Program_options): the options a user
// sees, any hidden ones that positional arguments fill, and --help printing the visible ones.
#pragma once

#include <boost/program_options.hpp>

namespace roam {
namespace tools {

// Stores argv into *vm against `visible` and `hidden`; positional arguments go to the hidden
// options `positional` names. Returns false when --help was given: `visible` has been printed to
// stdout and the tool exits 0. Otherwise notifies (the bound variables are filled) and returns
// true. Throws what Boost.Program_options throws on a bad command line.
bool parseCommandLine(int argc, char** argv, const boost::program_options::options_description& visible,
                      const boost::program_options::options_description& hidden,
                      const boost::program_options::positional_options_description& positional,
                      boost::program_options::variables_map* vm);

// The same for a tool that takes no positional argument.
bool parseCommandLine(int argc, char** argv, const boost::program_options::options_description& visible,
                      boost::program_options::variables_map* vm);

}  // namespace tools
}  // namespace roam
