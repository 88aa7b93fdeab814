// The memory limit: its parsing, and the check made before the big allocations.

#include "cwe/core/memory_limit.hpp"

#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cwe/core/error.hpp"

namespace cwe {
namespace {

const SourceLocation kOption{"--memory-limit"};

TEST(MemoryLimit, ParsesSizesAndShares) {
  constexpr std::size_t kMiB = std::size_t{1} << 20;
  EXPECT_EQ(parse_memory_limit("16G", kOption), 16 * 1024 * kMiB);
  EXPECT_EQ(parse_memory_limit("16g", kOption), 16 * 1024 * kMiB);
  EXPECT_EQ(parse_memory_limit("512MiB", kOption), 512 * kMiB);
  EXPECT_EQ(parse_memory_limit("64M", kOption), 64 * kMiB);
  EXPECT_EQ(parse_memory_limit("1.5GB", kOption), 1536 * kMiB);
  EXPECT_EQ(parse_memory_limit("1T", kOption), 1024 * 1024 * kMiB);
  EXPECT_EQ(parse_memory_limit("70000000000", kOption), std::size_t{70000000000});
  if (physical_memory() > 0) {
    const double half = 0.5 * static_cast<double>(physical_memory());
    EXPECT_NEAR(static_cast<double>(parse_memory_limit("50%", kOption)), half, 1.0);
  }
  for (const char* bad :
       {"", "G", "12x", "0", "-5G", "1K", "63M", "101%", "1e400", "16 G", "16GG", "nan", "1..5G"}) {
    SCOPED_TRACE(bad);
    try {
      parse_memory_limit(bad, kOption);
      ADD_FAILURE() << "expected an InputError";
    } catch (const InputError& e) {
      EXPECT_EQ(e.location().source, "--memory-limit");
      EXPECT_NE(e.message().find("expected a size"), std::string::npos) << e.what();
    }
  }
}

TEST(MemoryLimit, CheckNamesTheEstimateAndTheLimit) {
  set_memory_limit(std::size_t{1} << 30);
  EXPECT_EQ(memory_limit(), std::size_t{1} << 30);
  EXPECT_NO_THROW(check_memory(1e9, "the rays", kOption, "use fewer"));
  try {
    check_memory(43.2e9, "the rays", SourceLocation{"--resolution"}, "use a coarser resolution");
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "--resolution: error: the rays would need about 43.2 GB of memory, above the limit "
              "of 1.1 GB (--memory-limit): use a coarser resolution");
  }
  // A NaN estimate (an overflowed product) is refused too.
  EXPECT_THROW(check_memory(std::numeric_limits<double>::quiet_NaN(), "x", kOption, "y"),
               InputError);
  set_memory_limit(std::nullopt);
  if (physical_memory() > 0) {
    EXPECT_NEAR(static_cast<double>(memory_limit()), 0.8 * static_cast<double>(physical_memory()),
                1.0);
  }
}

TEST(MemoryLimit, BytesAsPeopleReadThem) {
  EXPECT_EQ(format_bytes(512), "512 B");
  EXPECT_EQ(format_bytes(3.2e6), "3.2 MB");
  EXPECT_EQ(format_bytes(43.15e9), "43.1 GB");
  EXPECT_EQ(format_bytes(2.5e12), "2.5 TB");
}

// The big arrays advised for huge pages get them where the system gives huge pages on request
// (transparent_hugepage "madvise", Debian's default; with "always" every big array gets them, and
// with "never" none). A range shorter than a huge page, or none, is left alone.
TEST(MemoryLimit, BigArraysAdvisedGetHugePages) {
  std::ifstream mode("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  std::getline(mode, modes);
  if (modes.find("[madvise]") == std::string::npos) {
    GTEST_SKIP() << "transparent huge pages: " << (modes.empty() ? "not found" : modes);
  }
  constexpr std::size_t kBytes = std::size_t{16} << 20;
  std::vector<char> big;
  big.reserve(kBytes);
  advise_huge_pages(big.data(), kBytes);
  big.assign(kBytes, 1);
  advise_huge_pages(nullptr, kBytes);
  advise_huge_pages(big.data(), 100);
  // The mapping that holds the array's first whole huge page (the advice splits the array's
  // mapping there), and the kB of it in huge pages.
  std::ifstream maps("/proc/self/smaps");
  constexpr std::uintptr_t kHuge = std::uintptr_t{1} << 21;
  const auto at = (reinterpret_cast<std::uintptr_t>(big.data()) + kHuge - 1) & ~(kHuge - 1);
  bool inside = false;
  long huge_kb = -1;
  for (std::string line; std::getline(maps, line);) {
    std::uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream range(line);
    if (range >> std::hex >> lo >> dash >> hi && dash == '-') {
      inside = lo <= at && at < hi;
    } else if (inside && line.starts_with("AnonHugePages:")) {
      huge_kb = std::stol(line.substr(14));
    }
  }
  ASSERT_GE(huge_kb, 0) << "the array's mapping was not found";
  // 16 MiB hold seven whole 2 MiB pages; the system may give fewer where its memory is
  // fragmented, but without the advice it gives none.
  EXPECT_GE(huge_kb, 2048);
}

TEST(PopulatePages, FaultsInTheRangesPagesAndLeavesTheirContents) {
  const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  constexpr std::size_t kPages = 16;
  void* mapped =
      ::mmap(nullptr, kPages * page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(mapped, MAP_FAILED);
  auto* bytes = static_cast<unsigned char*>(mapped);
  const auto resident = [&] {
    std::vector<unsigned char> in(kPages);
    EXPECT_EQ(::mincore(mapped, kPages * page, in.data()), 0);
    std::vector<int> pages;
    for (std::size_t k = 0; k < kPages; ++k) {
      if ((in[k] & 1) != 0) pages.push_back(static_cast<int>(k));
    }
    return pages;
  };
  bytes[page] = 7;  // page 1 written before
  ASSERT_EQ(resident(), std::vector<int>{1});
  // From inside page 1 to inside page 5: pages 1 to 5, the ends rounded out to whole pages.
  if (!populate_pages(bytes + page + 100, 4 * page)) {
    ::munmap(mapped, kPages * page);
    GTEST_SKIP() << "this system cannot fault pages in without writing them";
  }
  EXPECT_EQ(resident(), (std::vector<int>{1, 2, 3, 4, 5}));
  EXPECT_EQ(bytes[page], 7);
  EXPECT_TRUE(
      std::all_of(bytes + 2 * page, bytes + 6 * page, [](unsigned char b) { return b == 0; }));
  EXPECT_TRUE(populate_pages(nullptr, 0));
  ::munmap(mapped, kPages * page);
}

}  // namespace
}  // namespace cwe
