// The message of an input the library refuses: what every refusal test asks.
#pragma once

#include <string>

#include "softflow/common/error.hpp"
#include "softflow/io/case_config.hpp"

namespace softflow::test_support {

/// The InputError message `parse()` throws ("" if it returns).
template <class Parse>
std::string input_error_of(Parse&& parse) {
  try {
    parse();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// The InputError message of parsing `text` as the case file `name` ("" if it parses).
inline std::string case_error_of(const std::string& text, const std::string& name = "c.toml") {
  return input_error_of([&] { (void)io::parse_case(text, name); });
}

}  // namespace softflow::test_support
