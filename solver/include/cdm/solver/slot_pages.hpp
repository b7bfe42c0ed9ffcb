#pragma once
/// @file slot_pages.hpp
/// @brief Per-particle arrays that cost memory only where a process holds particles.
///
/// Among MPI processes every process keeps every particle's slot, but holds the state of
/// its own particles and ghosts only (rank_split.hpp); the other slots' values are stale.
/// zero_slots() sets such slots to zero and returns the pages that hold nothing else to
/// the system (madvise), where they read as zero and cost nothing until written. A
/// permutation (permute_array) writes only the values that are not zero into a zeroed
/// array, so it commits no page of slots that hold none. Neither changes a value a
/// process reads: the results are the same bits.
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace cdm {

class InArchive;

/// Runs of slots [first, last), increasing and disjoint.
using SlotRuns = std::vector<std::pair<std::size_t, std::size_t>>;

/// @p runs in order, those that touch or overlap joined into one: zero_slots() returns
/// only the pages that lie wholly inside one run.
SlotRuns merged(SlotRuns runs);
/// The runs of slots [0, @p n) where @p held(i) is false: those a process lets go of.
template <class Held>
SlotRuns runs_not_held(std::size_t n, Held&& held) {
  SlotRuns runs;
  for (std::size_t i = 0; i < n;) {
    if (held(i)) { ++i; continue; }
    const std::size_t first = i;
    while (i < n && !held(i)) ++i;
    runs.push_back({first, i});
  }
  return runs;
}
/// Set every slot of @p v in @p runs to zero. The pages lying wholly inside a run are
/// returned to the system; the others are written only where a value is not zero
/// already (so that a page never written stays uncommitted).
void zero_slots(std::vector<double>& v, const SlotRuns& runs);
/// zero_slots() of the bytes [@p first, @p last) of any array of numbers (doubles,
/// integer sums, flags): the whole pages inside returned to the system, the bytes of the
/// others written only where not zero.
void zero_bytes(void* first, void* last);
/// zero_slots() over the whole of @p v.
void zero_all(std::vector<double>& v);
/// Resize @p v to @p n slots; new slots are zero, their whole pages uncommitted. Where
/// @p v must grow beyond its capacity, it grows as reserve_zeroed() grows it.
void resize_zeroed(std::vector<double>& v, std::size_t n);
/// Make @p v @p n zeros, its former values dropped and its whole pages uncommitted.
void assign_zeroed(std::vector<double>& v, std::size_t n);
/// Give @p v room for @p capacity slots without committing pages for its zero values: a
/// reallocation (std::vector's own copies every value, zeros too) that copies only the
/// values that are not zero into pages that start uncommitted. The values keep their bits.
void reserve_zeroed(std::vector<double>& v, std::size_t capacity);
/// Return to the system the whole pages of [@p first, @p last), whose bytes are not read
/// again (they read as zero if they are).
void release_pages(const void* first, const void* last);
/// Set the values of @p v that are not zero to zero, writing nothing else.
void clear_nonzero(std::vector<double>& v);
/// Make @p v a copy of @p from's values, the same bits, writing only those that differ:
/// slots that read zero in both leave their pages uncommitted. Where @p v must grow
/// beyond its capacity, it grows as reserve_zeroed() grows it.
void copy_changed(std::vector<double>& v, const std::vector<double>& from);
/// Read a per-particle array of @p a (as InArchive::get, at most @p max_elements
/// values) of which this process keeps the slots of @p a's slot window only: the others
/// are read past and left zero, their pages uncommitted. An array whose length is not
/// the window's particle count, or without a window, is read whole.
void get_slots(InArchive& a, std::vector<double>& v, std::uint64_t max_elements = UINT64_MAX);

}  // namespace cdm
