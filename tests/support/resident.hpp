#pragma once
// Whether the memory page holding an address is resident (mincore): what the tests of
// arrays whose zero pages cost nothing (slot_pages.hpp) check.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdint>

#include <sys/mman.h>

namespace cdm_test {

inline bool resident(const void* p) {
  const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  const std::uintptr_t at = reinterpret_cast<std::uintptr_t>(p) / page * page;
  unsigned char in = 0;
  EXPECT_EQ(mincore(reinterpret_cast<void*>(at), page, &in), 0);
  return (in & 1) != 0;
}

}  // namespace cdm_test
