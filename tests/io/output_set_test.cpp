// Output folders replaced whole: staged, swapped in atomically, the leftovers of stopped runs
// removed, and a folder holding anything else refused.

#include "cwe/io/output_set.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>

#include "cwe/core/error.hpp"
#include "cwe/io/atomic_file.hpp"
#include "scratch_dir.hpp"

namespace cwe {
namespace {

namespace fs = std::filesystem;

void write(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

std::string read(const fs::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::set<std::string> names(const fs::path& folder) {
  std::set<std::string> out;
  for (const auto& entry : fs::directory_iterator(folder)) out.insert(entry.path().filename());
  return out;
}

const std::vector<std::string> kNames = {"a.csv", "b.json", "maps"};

TEST(OutputSet, ReplacesTheWholeFolderOnPublish) {
  const fs::path dir = test::fresh_scratch_dir("output-set-replace");
  const fs::path out = dir / "out";
  write(out / "a.csv", "old a");
  write(out / "maps" / "m1.png", "old map");
  {
    OutputSet set(out, kNames);
    EXPECT_EQ(set.staging().parent_path(), dir);
    write(set.staging() / "b.json", "new b");
    // Until published, the old set is untouched.
    EXPECT_EQ(read(out / "a.csv"), "old a");
    set.publish();
  }
  EXPECT_EQ(names(out), (std::set<std::string>{"b.json"}));
  EXPECT_EQ(read(out / "b.json"), "new b");
  EXPECT_EQ(names(dir), (std::set<std::string>{"out"}));  // no staging, no old set
}

// Files committed in the staging folder are synced together when it is published, not one by
// one: what they hold is what was written, in subfolders too, and a file that cannot be synced
// is an error naming it.
TEST(OutputSet, StagedFilesAreSyncedTogetherOnPublish) {
  const fs::path dir = test::fresh_scratch_dir("output-set-synced");
  {
    OutputSet set(dir / "out", kNames);
    write_file_atomically(set.staging() / "a.csv", "a");
    AtomicFileWriter map(set.staging() / "maps" / "m1.svg");
    map.append("<svg");
    EXPECT_EQ(map.writeback_pending(), 4u);
    map.start_writeback();  // what follows is written too
    EXPECT_EQ(map.writeback_pending(), 0u);
    map.append("/>");
    EXPECT_EQ(map.writeback_pending(), 2u);
    map.overwrite(1, "SVG");  // bytes already appended, handed to the system or still buffered
    map.overwrite(4, "|");
    map.commit();
    EXPECT_THROW(map.start_writeback(), InputError);  // committed: nothing more to write
    set.publish();
  }
  EXPECT_EQ(read(dir / "out" / "a.csv"), "a");
  EXPECT_EQ(read(dir / "out" / "maps" / "m1.svg"), "<SVG|>");
  EXPECT_NO_THROW(sync_folder(dir / "out"));
  try {
    sync_folder(dir / "gone");
    ADD_FAILURE() << "a missing folder was synced";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gone"), std::string::npos) << e.what();
  }
}

// Files and folders synced ahead (their syncs started while the rest is written) are published
// with the rest; a sync ahead that fails fails the publication, naming the file, and leaves the
// old set.
TEST(OutputSet, FilesSyncedAheadArePublishedWithTheRest) {
  const fs::path dir = test::fresh_scratch_dir("output-set-ahead");
  const std::string big(3 << 20, 'x');
  {
    OutputSet set(dir / "out", kNames);
    write_file_atomically(set.staging() / "maps" / "m1.png", "map 1");
    write_file_atomically(set.staging() / "maps" / "m2.png", "map 2");
    AtomicFileWriter file(set.staging() / "a.csv");
    file.append(big);
    file.commit();
    set.sync_ahead({set.staging() / "maps"});
    set.sync_ahead({file.path()});
    write_file_atomically(set.staging() / "b.json", "b");
    set.publish();
  }
  EXPECT_EQ(read(dir / "out" / "a.csv"), big);
  EXPECT_EQ(read(dir / "out" / "b.json"), "b");
  EXPECT_EQ(read(dir / "out" / "maps" / "m2.png"), "map 2");
  EXPECT_EQ(names(dir), (std::set<std::string>{"out"}));

  {
    OutputSet set(dir / "out", kNames);
    write_file_atomically(set.staging() / "b.json", "new b");
    set.sync_ahead({set.staging() / "b.json", set.staging() / "a.csv"});  // a.csv never written
    try {
      set.publish();
      ADD_FAILURE() << "published with a file that could not be synced";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("a.csv"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(read(dir / "out" / "b.json"), "b");  // the old set
  EXPECT_EQ(names(dir), (std::set<std::string>{"out"}));

  {
    OutputSet set(dir / "out", kNames);
    write_file_atomically(set.staging() / "a.csv", "half");
    set.sync_ahead({set.staging() / "a.csv"});
  }  // an error on the way, a sync still running: the staging folder goes, the old set stays
  EXPECT_EQ(read(dir / "out" / "a.csv"), big);
  EXPECT_EQ(names(dir), (std::set<std::string>{"out"}));
}

TEST(OutputSet, ANewFolderIsRenamedIntoPlace) {
  const fs::path dir = test::fresh_scratch_dir("output-set-new");
  {
    OutputSet set(dir / "deeper" / "out", kNames);
    write(set.staging() / "a.csv", "a");
    set.publish();
  }
  EXPECT_EQ(read(dir / "deeper" / "out" / "a.csv"), "a");
}

TEST(OutputSet, AnUnpublishedSetLeavesTheOldOneAndNoStaging) {
  const fs::path dir = test::fresh_scratch_dir("output-set-unpublished");
  write(dir / "out" / "a.csv", "old a");
  {
    OutputSet set(dir / "out", kNames);
    write(set.staging() / "a.csv", "half");
  }  // an error on the way: never published
  EXPECT_EQ(read(dir / "out" / "a.csv"), "old a");
  EXPECT_EQ(names(dir), (std::set<std::string>{"out"}));
}

TEST(OutputSet, LeftoversOfStoppedRunsAreRemoved) {
  const fs::path dir = test::fresh_scratch_dir("output-set-leftovers");
  // A pid that cannot be running (above the kernel's pid_max of 4,194,304).
  write(dir / ".out.cwe-staging-999999999" / "a.csv", "killed run");
  write(dir / ".out.cwe-staging-" / "a.csv", "no pid: not ours to remove");
  const std::string running = ".out.cwe-staging-" + std::to_string(::getppid());
  write(dir / running / "a.csv", "a run still going");
  // A run stopped between the two renames of the fallback: its old set goes back.
  write(dir / ".out.cwe-old-999999998" / "a.csv", "previous set");
  { OutputSet set(dir / "out", kNames); }
  EXPECT_EQ(names(dir), (std::set<std::string>{"out", ".out.cwe-staging-", running}));
  EXPECT_EQ(read(dir / "out" / "a.csv"), "previous set");
}

TEST(OutputSet, AFolderHoldingOtherFilesIsRefused) {
  const fs::path dir = test::fresh_scratch_dir("output-set-foreign");
  write(dir / "out" / "a.csv", "old a");
  write(dir / "out" / "notes.txt", "the user's");
  try {
    OutputSet set(dir / "out", kNames, SourceLocation{"job.json", 3, 10});
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().line, 3);
    EXPECT_NE(e.message().find("holds notes.txt, which is not an output"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(names(dir / "out"), (std::set<std::string>{"a.csv", "notes.txt"}));
  EXPECT_EQ(names(dir), (std::set<std::string>{"out"}));
  // A file where the folder should be, and the working folder itself.
  write(dir / "file", "x");
  EXPECT_THROW(OutputSet(dir / "file", kNames), InputError);
  EXPECT_THROW(OutputSet(fs::current_path(), kNames), InputError);
  EXPECT_THROW(OutputSet(".", kNames), InputError);
}

}  // namespace
}  // namespace cwe
