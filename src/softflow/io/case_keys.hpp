// The keys of a softflow case file, each declared once (case_keys.cpp): the reader, `softflow
// check`'s printout, the sweep's key types and docs/case_file_keys.md are derived from them.
#pragma once

#include <vector>

#include "softflow/io/case_config.hpp"
#include "softflow/io/key_schema.hpp"

namespace softflow::io {

struct CaseKeys {
  // The schema points into the tables' keys: moving keeps them where they
  // are (vector buffers move), copying would not.
  CaseKeys() = default;
  CaseKeys(CaseKeys&&) = default;
  CaseKeys(const CaseKeys&) = delete;
  CaseKeys& operator=(const CaseKeys&) = delete;

  /// Every table but [[objects]], filling the CaseConfig.
  std::vector<schema::Table<CaseConfig>> tables;
  /// [[objects]]: one ObjectConfig per entry.
  schema::Table<ObjectConfig> objects;
  /// All tables by name, in the order they are read, printed and documented,
  /// and the aliases users write for keys.
  schema::Schema schema;

  [[nodiscard]] const schema::Table<CaseConfig>* table(std::string_view name) const;
};

/// A plain file-name component (no '/', '\\', control characters, "." or
/// "..", not only spaces): a case name, since it names the output directory.
bool is_plain_name(std::string_view name);

/// The declarations (built once).
const CaseKeys& case_keys();

}  // namespace softflow::io
