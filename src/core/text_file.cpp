#include "cwe/core/text_file.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "cwe/core/error.hpp"

namespace cwe {

namespace {

std::string read_whole(const std::string& path, const std::string& what, bool text_only) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw InputError(SourceLocation{path}, "the " + what + " is a directory");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(SourceLocation{path}, "cannot open the " + what);
  // In blocks, so that a device or pipe that never ends (/dev/zero) or is not text stops early.
  std::string text;
  std::string block(std::size_t{1} << 16, '\0');
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    const auto got = static_cast<std::size_t>(in.gcount());
    if (text_only && block.find('\0') < got) {
      text.append(block.data(), got);
      throw InputError(location_of(text, text.find('\0'), path),
                       "the " + what + " holds a NUL byte: not a text file");
    }
    if (text.size() + got > kLargestTextFile) {
      throw InputError(SourceLocation{path},
                       "the " + what + " is larger than " + std::to_string(kLargestTextFile >> 30) +
                           " GiB read whole (a pipe or device; a regular file of any size is "
                           "mapped instead)");
    }
    text.append(block.data(), got);
  }
  if (in.bad()) throw InputError(SourceLocation{path}, "cannot read the " + what);
  return text;
}

}  // namespace

std::string read_text_file(const std::string& path, const std::string& what) {
  return read_whole(path, what, true);
}

std::string read_binary_file(const std::string& path, const std::string& what) {
  return read_whole(path, what, false);
}

MappedText::MappedText(const std::string& path, const std::string& what) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    throw InputError(SourceLocation{path}, "cannot open the " + what + ": " + std::strerror(errno));
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || S_ISDIR(st.st_mode) || !S_ISREG(st.st_mode) || st.st_size == 0) {
    ::close(fd);
    if (S_ISDIR(st.st_mode)) {
      throw InputError(SourceLocation{path}, "the " + what + " is a directory");
    }
    owned_ = read_text_file(path, what);  // a pipe, a device, an empty file: read it
    text_ = owned_;
    return;
  }
  size_ = static_cast<std::size_t>(st.st_size);
  map_ = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
  ::close(fd);
  if (map_ == MAP_FAILED) {
    map_ = nullptr;
    throw InputError(SourceLocation{path}, "cannot read the " + what + ": " + std::strerror(errno));
  }
  ::madvise(map_, size_, MADV_SEQUENTIAL);
  text_ = std::string_view(static_cast<const char*>(map_), size_);
}

MappedText::~MappedText() {
  if (map_ != nullptr) ::munmap(map_, size_);
}

void MappedText::release_before(std::size_t offset) {
  // Every 16 MiB of progress, all the pages before (a loop may have brought early ones back).
  constexpr std::size_t kStep = std::size_t{16} << 20;
  if (map_ == nullptr || offset < released_ + kStep) return;
  const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  const std::size_t end = std::min(offset, size_) / page * page;
  ::madvise(map_, end, MADV_DONTNEED);
  released_ = end;
}

SourceLocation location_of(std::string_view text, std::size_t offset, const std::string& source) {
  int line = 1, column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return {source, line, column};
}

}  // namespace cwe
