// docs/scene-reference.md documents every key the loader accepts, and nothing else:
// the first column of each reference table must equal scene_schema_keys().
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>
#include <string>

#include "cdm/solver/scene_loader.hpp"

TEST(SceneReference, EveryKeyIsDocumented) {
  std::ifstream in(std::string(CDM_SOURCE_DIR) + "/docs/scene-reference.md");
  ASSERT_TRUE(in) << "docs/scene-reference.md is missing";
  std::set<std::string> documented;
  // A reference row starts "| `key` |".
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("| `", 0) != 0) continue;
    const auto end = line.find('`', 3);
    if (end == std::string::npos || line.find('|', end) == std::string::npos) continue;
    documented.insert(line.substr(3, end - 3));
  }
  const auto keys = cdm::scene_schema_keys();
  const std::set<std::string> accepted(keys.begin(), keys.end());
  std::string missing, extra;
  for (const auto& k : accepted)
    if (!documented.count(k)) missing += " " + k;
  for (const auto& k : documented)
    if (!accepted.count(k)) extra += " " + k;
  EXPECT_TRUE(missing.empty()) << "keys the loader accepts but the reference does not document:" << missing;
  EXPECT_TRUE(extra.empty()) << "keys documented but not accepted by the loader:" << extra;
}

// The row of each key that takes a keyword names every keyword the loader accepts there.
TEST(SceneReference, EveryKeywordIsDocumented) {
  std::ifstream in(std::string(CDM_SOURCE_DIR) + "/docs/scene-reference.md");
  ASSERT_TRUE(in) << "docs/scene-reference.md is missing";
  std::map<std::string, std::string> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("| `", 0) != 0) continue;
    const auto end = line.find('`', 3);
    if (end != std::string::npos) rows[line.substr(3, end - 3)] = line;
  }
  for (const auto& [key, keywords] : cdm::scene_schema_keywords()) {
    ASSERT_TRUE(rows.count(key)) << key << " has no row in the reference";
    for (const auto& k : keywords)
      EXPECT_NE(rows[key].find("\"" + k + "\""), std::string::npos) << key << ": keyword \"" << k << "\" is not documented";
  }
}
