#include "cdm/solver/platform.hpp"

#include <cctype>
#include <fstream>
#include <string>

namespace cdm {

std::size_t parse_cache_size(std::string_view text) {
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.remove_suffix(1);
  std::size_t digits = 0, value = 0;
  while (digits < text.size() && std::isdigit(static_cast<unsigned char>(text[digits]))) {
    if (value > (std::size_t{1} << 40)) return 0;  // beyond any cache
    value = value * 10 + static_cast<std::size_t>(text[digits] - '0');
    ++digits;
  }
  if (digits == 0) return 0;
  const std::string_view suffix = text.substr(digits);
  if (suffix.empty()) return value;
  if (suffix == "K") return value << 10;
  if (suffix == "M") return value << 20;
  if (suffix == "G") return value << 30;
  return 0;
}

namespace {

std::size_t read_last_level_cache() {
  int best_level = 0;
  std::size_t best = 0;
  for (int index = 0; index < 16; ++index) {
    const std::string dir = "/sys/devices/system/cpu/cpu0/cache/index" + std::to_string(index) + "/";
    std::ifstream level_file(dir + "level"), size_file(dir + "size");
    if (!level_file || !size_file) continue;  // indices need not be contiguous
    int level = 0;
    std::string size;
    if (!(level_file >> level) || !(size_file >> size)) continue;
    const std::size_t bytes = parse_cache_size(size);
    if (bytes == 0) continue;
    if (level > best_level || (level == best_level && bytes > best)) {
      best_level = level;
      best = bytes;
    }
  }
  return best ? best : fallback_cache_bytes;
}

}  // namespace

std::size_t last_level_cache_bytes() {
  static const std::size_t bytes = read_last_level_cache();
  return bytes;
}

}  // namespace cdm
