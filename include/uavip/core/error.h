#pragma once
/// \file
/// Errors. Bad input or setup throws InputError whose message names the file (or
/// option), the value and what to do; the CLI prints it on one line and exits 2.
/// "No plan" or "surface blocked" is a returned status, never an exception.

#include <stdexcept>
#include <string>

namespace uavip {

/// Bad user input: a file, a value, an option. CLI exit code 2.
class InputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Throws InputError("<where>: <what>") unless cond holds.
void require(bool cond, const std::string& where, const std::string& what);

/// Throws InputError unless value > 0 and finite: "<where>: <name> must be > 0, got <value>".
void requirePositive(double value, const std::string& where, const std::string& name);

/// Throws InputError unless ok: "<where>: <name> must be <range>, got <value>".
void requireThat(bool ok, const std::string& where, const std::string& name,
                 const std::string& range, double value);

}  // namespace uavip
