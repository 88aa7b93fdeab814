#include "cwe/core/memory_limit.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <string>

#include <fmt/format.h>

#include "cwe/core/numbers.hpp"

namespace cwe {
namespace {

// 0: the default.
std::atomic<std::size_t> g_limit{0};

constexpr double kDefaultShare = 0.8;
constexpr double kSmallestLimit = 64.0 * 1024 * 1024;

}  // namespace

std::size_t physical_memory() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return 0;
  return static_cast<std::size_t>(pages) * static_cast<std::size_t>(page);
}

std::size_t memory_limit() {
  if (const std::size_t set = g_limit.load(); set != 0) return set;
  const std::size_t physical = physical_memory();
  if (physical == 0) return static_cast<std::size_t>(-1);
  return static_cast<std::size_t>(kDefaultShare * static_cast<double>(physical));
}

void set_memory_limit(std::optional<std::size_t> bytes) { g_limit.store(bytes.value_or(0)); }

std::string format_bytes(double bytes) {
  if (std::isnan(bytes)) return "an unknown amount";
  if (bytes < 1e3) return fmt::format("{:.0f} B", bytes);
  if (bytes < 1e6) return fmt::format("{:.1f} kB", bytes / 1e3);
  if (bytes < 1e9) return fmt::format("{:.1f} MB", bytes / 1e6);
  if (bytes < 1e12) return fmt::format("{:.1f} GB", bytes / 1e9);
  return fmt::format("{:.3g} TB", bytes / 1e12);
}

void check_memory(double bytes, std::string_view what, const SourceLocation& where,
                  std::string_view remedy) {
  const auto limit = static_cast<double>(memory_limit());
  if (!std::isnan(bytes) && bytes <= limit) return;  // NaN (an overflowed estimate) is refused
  throw InputError(where, fmt::format("{} would need about {} of memory, above the limit of {} "
                                      "(--memory-limit): {}",
                                      what, format_bytes(bytes), format_bytes(limit), remedy));
}

std::size_t parse_memory_limit(std::string_view text, const SourceLocation& where) {
  const auto fail = [&]() -> std::size_t {
    throw InputError(where, fmt::format("'{}': expected a size such as 16G, 4096M or 50%, "
                                        "at least 64M",
                                        text));
  };
  std::size_t digits = 0;
  while (digits < text.size() &&
         (std::isdigit(static_cast<unsigned char>(text[digits])) != 0 || text[digits] == '.')) {
    ++digits;
  }
  const NumberList list = parse_number_list(text.substr(0, digits));
  if (list.bad || list.values.size() != 1 || !(list.values[0] > 0.0)) return fail();
  const double* number = &list.values[0];
  std::string unit(text.substr(digits));
  for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  double bytes = *number;
  if (unit == "%") {
    if (*number > 100.0) return fail();
    bytes = *number / 100.0 * static_cast<double>(physical_memory());
  } else {
    if (unit.ends_with("IB")) {
      unit.erase(unit.size() - 2);
    } else if (unit.ends_with("B")) {
      unit.pop_back();
    }
    static constexpr std::string_view kUnits = "KMGT";
    if (unit.size() > 1) return fail();
    if (unit.size() == 1) {
      const std::size_t power = kUnits.find(unit[0]);
      if (power == kUnits.npos) return fail();
      bytes *= std::pow(1024.0, static_cast<double>(power + 1));
    }
  }
  if (!(bytes >= kSmallestLimit) || bytes > 1e18) return fail();
  return static_cast<std::size_t>(bytes);
}

void advise_huge_pages(const void* data, std::size_t bytes) {
  constexpr std::uintptr_t kHuge = kHugePageBytes;
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + kHuge - 1) & ~(kHuge - 1);
  const std::uintptr_t last = (begin + bytes) & ~(kHuge - 1);
  if (data == nullptr || last <= first) return;
  ::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
}

bool populate_pages(const void* data, std::size_t bytes) {
#ifdef MADV_POPULATE_WRITE
  if (data == nullptr || bytes == 0) return true;
  const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  const auto begin = reinterpret_cast<std::uintptr_t>(data) & ~(page - 1);
  const std::uintptr_t end = reinterpret_cast<std::uintptr_t>(data) + bytes;
  return ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_POPULATE_WRITE) == 0;
#else
  (void)data;
  (void)bytes;
  return false;
#endif
}

}  // namespace cwe
