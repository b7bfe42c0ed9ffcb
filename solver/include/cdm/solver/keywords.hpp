#pragma once
/// @file keywords.hpp
/// @brief One {keyword, value} table per choice a scene makes. The scene loader parses
/// with it, to_string prints with it and error messages list its keywords, so each
/// keyword is spelled once, next to its enum.
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace cdm {

template <class E>
struct Keyword {
  const char* name;
  E value;
};

/// The keywords of one choice, in the order messages list them.
template <class E, std::size_t N>
using Keywords = std::array<Keyword<E>, N>;

/// The keyword of @p value ("?" if the table lacks it).
template <class E, std::size_t N>
constexpr const char* keyword_of(const Keywords<E, N>& table, E value) {
  for (const auto& k : table)
    if (k.value == value) return k.name;
  return "?";
}

/// The value that @p name spells, if any.
template <class E, std::size_t N>
std::optional<E> keyword_value(const Keywords<E, N>& table, std::string_view name) {
  for (const auto& k : table)
    if (name == k.name) return k.value;
  return std::nullopt;
}

/// The keywords for which @p keep(value) holds, quoted and joined as messages list them:
/// "\"a\", \"b\" or \"c\"". @p first, when given, leads the list (e.g. "none").
template <class E, std::size_t N, class Keep>
std::string keyword_list(const Keywords<E, N>& table, Keep keep, const char* first = nullptr) {
  std::array<const char*, N + 1> names{};
  std::size_t n = 0;
  if (first) names[n++] = first;
  for (const auto& k : table)
    if (keep(k.value)) names[n++] = k.name;
  std::string s;
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) s += i + 1 == n ? " or " : ", ";
    s += '"';
    s += names[i];
    s += '"';
  }
  return s;
}

template <class E, std::size_t N>
std::string keyword_list(const Keywords<E, N>& table) {
  return keyword_list(table, [](E) { return true; });
}

}  // namespace cdm
