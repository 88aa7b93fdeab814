#pragma once
// The memory a run may take (`--memory-limit`, default 80 % of physical memory), checked before
// the big allocations whose size the input decides — the dexel rays of the stock (set by the
// resolution and the stock's size) and the moves of the programs — so a resolution or program
// far too big ends in an error naming the option and the estimate, not in the system killing the
// process (or swapping for hours) half-way through a run.
//
// The limit is one per process, like the thread count: the command line sets it once, before the
// job starts; the library reads it where it allocates. The same big allocations are advised onto
// huge pages here (advise_huge_pages).

#include <cstddef>
#include <optional>
#include <string_view>

#include "cwe/core/error.hpp"

namespace cwe {

// Bytes of physical memory of this machine (0 when the system does not say).
std::size_t physical_memory();

// The limit in bytes: the one set, else 80 % of physical memory (unlimited when that is unknown).
std::size_t memory_limit();
// Sets the limit (nullopt: back to the default).
void set_memory_limit(std::optional<std::size_t> bytes);

// Bytes as people read them: "512 B", "3.2 MB", "43.1 GB" (powers of 1000).
std::string format_bytes(double bytes);

// A transparent huge page: the unit advise_huge_pages() asks for, and a block of pages worth
// faulting in at once (populate_pages).
inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

// Asks the system to back [data, data + bytes) with transparent huge pages (2 MiB) where it has
// them, for the big arrays written whole at once (the stock's rays, the contoured stock's mesh):
// their first writes otherwise fault their memory in 4 KiB at a time, 20,000 faults on the
// pocketing bench (docs/performance.md). Call it before the memory is first written; a hint that
// never fails (the part of the range in whole 2 MiB pages is advised).
void advise_huge_pages(const void* data, std::size_t bytes);

// Faults in the pages of [data, data + bytes) (whole pages: the range's ends are rounded out)
// as a first write would, without writing them: their contents stay as they are. A thread with
// nothing else to do can so take the page faults of an array that another thread is about to
// fill, and several threads can share those of one array: on the virtual machines cwe is
// measured on, a first write to a page costs a hundred times a later one (docs/performance.md).
// Returns false where the system cannot (Linux before 5.14, or a range it refuses), which changes
// nothing but the time taken.
bool populate_pages(const void* data, std::size_t bytes);

// Throws InputError at `where` when `bytes` (an estimate of what `what` needs, e.g. "the dexel
// rays of a 120 × 80 × 40 mm stock at 0.002 mm") is above the limit. The message gives both
// figures and what to change.
void check_memory(double bytes, std::string_view what, const SourceLocation& where,
                  std::string_view remedy);

// Parses a --memory-limit value: a number of bytes with an optional unit K, M, G, T (powers of
// 1024, "B" and "iB" optional, e.g. 16G, 512MiB), or a percentage of physical memory ("50%").
// Throws InputError at `where` for anything else, or for a limit below 64 MiB.
std::size_t parse_memory_limit(std::string_view text, const SourceLocation& where);

}  // namespace cwe
