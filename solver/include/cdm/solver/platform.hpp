#pragma once
/// @file platform.hpp
/// @brief What the solver asks of the machine it runs on: the size of its largest
/// cache, which decides whether a loop's data can stay in cache from one step to the
/// next (ContactModule's partner prefetch). Never the results: only how they are fetched.
#include <cstddef>
#include <string_view>

namespace cdm {

/// Assumed when the machine does not say (no Linux sysfs): 32 MiB, a server's L3.
inline constexpr std::size_t fallback_cache_bytes = std::size_t{32} << 20;

/// A cache size as Linux's sysfs writes it ("32768K", "1M", "512") in bytes; 0 when
/// @p text is not one (empty, no digits, an unknown suffix, trailing characters).
std::size_t parse_cache_size(std::string_view text);

/// The size [bytes] of the largest cache of CPU 0 (the highest level listed under
/// /sys/devices/system/cpu/cpu0/cache), read once; fallback_cache_bytes if none can be
/// read. Not sysconf(_SC_LEVEL3_CACHE_SIZE): glibc reports 384 MiB for a 32 MiB L3 on
/// the AMD EPYC guests cdm is benchmarked on. The size the processor has, not what one
/// core gets of it (bench/cache_probe measures that), so a footprint between the two is
/// taken for cached when it is not; a measured size, varying from run to run, would make
/// the choices that depend on it less predictable.
std::size_t last_level_cache_bytes();

}  // namespace cdm
