// Atomic writes and the dataset folder's rules: fresh, refused, forced, resumed, rolled back.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "trainsim/core/error.hpp"
#include "trainsim/io/dataset_writer.hpp"
#include "trainsim/io/file_io.hpp"

namespace trainsim::io {
namespace {
namespace fs = std::filesystem;

class TempDir : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("trainsim-io-" +
             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }
  std::size_t countTemporaries() const {
    std::size_t n = 0;
    for (const auto& e : fs::recursive_directory_iterator(root_))
      n += isAtomicTemporary(e.path());
    return n;
  }
  fs::path root_;
};

using AtomicWrite = TempDir;
using Dataset = TempDir;

TEST_F(AtomicWrite, ReplacesWholeFileAndLeavesNoTemporary) {
  writeFileAtomic(root_ / "a.txt", "first");
  writeFileAtomic(root_ / "a.txt", "second");
  EXPECT_EQ(readFile(root_ / "a.txt"), "second");
  EXPECT_EQ(countTemporaries(), 0u);
}

TEST_F(AtomicWrite, FailureNamesTheFileAndLeavesNothing) {
  try {
    writeFileAtomic(root_ / "missing" / "a.txt", "x");
    FAIL() << "no exception";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("missing/a.txt"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No such file or directory"), std::string::npos);
  }
  EXPECT_EQ(countTemporaries(), 0u);
}

// A streamed file larger than its buffer: until commit() the old file stays whole; a stream
// abandoned part-way (an exception) leaves the old file and no temporary.
TEST_F(AtomicWrite, StreamedFileAppearsWholeOnCommitAndNotAtAllWhenAbandoned) {
  writeFileAtomic(root_ / "big.csv", "old\n");
  const std::string line(1000, 'x');
  {
    AtomicFile f(root_ / "big.csv");
    for (int i = 0; i < 3000; ++i)  // 3 MB: several buffer flushes
      f.write(line);
    EXPECT_EQ(readFile(root_ / "big.csv"), "old\n");
    EXPECT_EQ(countTemporaries(), 1u);
  }  // abandoned
  EXPECT_EQ(readFile(root_ / "big.csv"), "old\n");
  EXPECT_EQ(countTemporaries(), 0u);
  AtomicFile f(root_ / "big.csv");
  for (int i = 0; i < 3000; ++i)
    f.write(line);
  f.commit();
  EXPECT_EQ(readFile(root_ / "big.csv").size(), 3'000'000u);
  EXPECT_EQ(countTemporaries(), 0u);
}

TEST_F(AtomicWrite, AppendFileFlushesAndTruncates) {
  AppendFile f(root_ / "log.csv");
  f.write("a,b\n");
  EXPECT_EQ(f.flush(), 4);
  f.write("1,2\n");
  f.truncate(4);
  f.write("3,4\n");
  EXPECT_EQ(f.flush(), 8);
  EXPECT_EQ(readFile(root_ / "log.csv"), "a,b\n3,4\n");
  EXPECT_THROW(AppendFile(root_ / "log.csv", 100), IoError);  // shorter than its checkpoint
}

const RunIdentity kRun{"0123456789abcdef", 42};

// No NaN or infinity reaches an output: a formatted non-finite field is refused, words that
// merely contain the letters are not.
TEST_F(AtomicWrite, NonFiniteFieldsAreRefused) {
  for (const char* bad : {"1,nan,2\n", "1,-nan\n", "inf,0\n", "0,-inf\n", "[1,inf]"})
    EXPECT_THROW(requireFinite(bad, "x.csv"), RuntimeError) << bad;
  for (const char* good : {"t_ns,info,finance,nano\n", "1e-9,2.5\n", "[1,2]"})
    EXPECT_NO_THROW(requireFinite(good, "x.csv")) << good;
  AppendFile f(root_ / "a.csv");
  EXPECT_THROW(f.write("0,nan\n"), RuntimeError);
  EXPECT_EQ(f.flush(), 0);
}

TEST_F(Dataset, FreshRunCreatesLayoutAndFinishRemovesCheckpoint) {
  const fs::path out = root_ / "out";
  {
    DatasetWriter w(out, io::DatasetLayout(0), kRun, {});
    EXPECT_EQ(w.start(), DatasetWriter::Start::kFresh);
    EXPECT_TRUE(fs::is_directory(out / "sequences" / "00"));
    EXPECT_TRUE(fs::exists(out / ".trainsim" / "checkpoint.json"));
    w.writeFile("scenario.json", "{}\n");
    w.appendFile("sequences/00/times.txt").write("0.000000000\n");
    w.finish({{"scenario_hash", kRun.scenario_hash}, {"seed", kRun.seed}});
  }
  EXPECT_TRUE(fs::exists(out / "manifest.json"));
  EXPECT_FALSE(fs::exists(out / ".trainsim"));
  EXPECT_EQ(readFile(out / "sequences/00/times.txt"), "0.000000000\n");
}

TEST_F(Dataset, RefusesForeignNonEmptyFolderUnlessForcedAndKeepsForeignFiles) {
  writeFileAtomic(root_ / "notes.txt", "mine");
  fs::create_directories(root_ / "sequences" / "07");
  EXPECT_THROW(DatasetWriter(root_, DatasetLayout(0), kRun, {}), ConfigError);
  {
    DatasetWriter w(root_, DatasetLayout(0), kRun, {.force = true});
    w.finish({});
  }
  EXPECT_EQ(readFile(root_ / "notes.txt"), "mine");
  EXPECT_FALSE(fs::exists(root_ / "sequences" / "07"));  // TrainSim's own entry was removed
}

TEST_F(Dataset, CompleteDatasetNeedsForceAndResumeIsANoOpForTheSameRun) {
  {
    DatasetWriter(root_, DatasetLayout(0), kRun, {})
        .finish({{"scenario_hash", kRun.scenario_hash}, {"seed", 42}});
  }
  EXPECT_THROW(DatasetWriter(root_, DatasetLayout(0), kRun, {}), ConfigError);
  EXPECT_EQ(DatasetWriter(root_, DatasetLayout(0), kRun, {.resume = true}).start(),
            DatasetWriter::Start::kAlreadyComplete);
  EXPECT_THROW(DatasetWriter(root_, DatasetLayout(0), {"ffffffffffffffff", 42}, {.resume = true}),
               ConfigError);
  EXPECT_THROW(DatasetWriter(root_, DatasetLayout(0), kRun, {.force = true, .resume = true}),
               ConfigError);
}

TEST_F(Dataset, ResumeCutsAppendFilesBackToTheCheckpointAndDropsTemporaries) {
  {
    DatasetWriter w(root_, DatasetLayout(0), kRun, {});
    auto& f = w.appendFile("sequences/00/imu.csv");
    f.write("header\nrow1\n");
    w.checkpoint(5, {{"imu", {{"bias", 0.25}}}});
    f.write("row2-partial");
    f.flush();
    writeFileAtomic(root_ / "sequences/00/.000001.bin.tmp.999", "junk");  // killed mid-write
    // Simulate kill -9: skip the destructor's roll-back by leaking nothing but not finishing.
    std::ofstream(root_ / "sequences/00/imu.csv", std::ios::app) << "more";
  }
  EXPECT_THROW(DatasetWriter(root_, DatasetLayout(0), kRun, {}), ConfigError);  // needs --resume
  EXPECT_THROW(DatasetWriter(root_, DatasetLayout(0), {"ffffffffffffffff", 42}, {.resume = true}),
               ConfigError);
  DatasetWriter w(root_, DatasetLayout(0), kRun, {.resume = true});
  EXPECT_EQ(w.start(), DatasetWriter::Start::kResume);
  EXPECT_EQ(w.resumeSample(), 5);
  EXPECT_EQ(w.resumeState()["imu"]["bias"], 0.25);
  w.appendFile("sequences/00/imu.csv");
  EXPECT_EQ(readFile(root_ / "sequences/00/imu.csv"), "header\nrow1\n");
  EXPECT_EQ(countTemporaries(), 0u);
}

TEST_F(Dataset, AbandonedRunRollsAppendFilesBackToLastCheckpoint) {
  {
    DatasetWriter w(root_, DatasetLayout(0), kRun, {});
    auto& f = w.appendFile("sequences/00/gnss.csv");
    f.write("a\n");
    w.checkpoint(1, nullptr);
    f.write("b\n");
    f.flush();
  }  // destroyed without finish(): an exception unwound the run
  EXPECT_EQ(readFile(root_ / "sequences/00/gnss.csv"), "a\n");
  EXPECT_FALSE(fs::exists(root_ / "manifest.json"));
}

// Defence in depth behind the scenario's name rules: no path the writer is handed can leave the
// dataset folder, whatever a sensor asks for.
TEST_F(Dataset, EveryPathStaysInsideTheFolder) {
  DatasetWriter w(root_ / "out", DatasetLayout(0), kRun, {});
  for (const char* bad : {"../escape.csv", "sequences/00/../../../x.csv", "/tmp/abs.csv", "",
                          "sequences/./00/x.csv"}) {
    EXPECT_THROW(w.appendFile(bad), RuntimeError) << bad;
    EXPECT_THROW(w.writeFile(bad, "x"), RuntimeError) << bad;
  }
  EXPECT_FALSE(fs::exists(root_ / "escape.csv"));
  EXPECT_FALSE(fs::exists("/tmp/abs.csv"));
  EXPECT_TRUE(DatasetLayout::isInside("sequences/00/imu.csv"));
}

// An append file that cannot be opened (a name longer than the file system allows) is an
// IoError naming it, not a crash; the run had no complete frame, so the folder it made goes.
TEST_F(Dataset, AppendFileThatCannotBeOpenedFailsCleanlyAndTheRunLeavesNothing) {
  {
    DatasetWriter w(root_ / "out", DatasetLayout(0), kRun, {});
    const std::string long_name = "sequences/00/" + std::string(300, 'x') + ".csv";
    EXPECT_THROW(w.appendFile(long_name), IoError);
    w.appendFile("sequences/00/ok.csv").write("a\n");
  }
  EXPECT_FALSE(fs::exists(root_ / "out"));
}

// In a folder that existed (empty), a run failing before its first frame leaves it empty.
TEST_F(Dataset, RunFailingBeforeItsFirstFrameLeavesAnExistingFolderAsItWas) {
  {
    DatasetWriter w(root_, DatasetLayout(0), kRun, {});
    w.writeFile("scenario.json", "{}");
    w.appendFile("sequences/00/imu.csv").write("header\n");
  }
  EXPECT_TRUE(fs::exists(root_));
  EXPECT_TRUE(fs::is_empty(root_));
}

// --resume trusts no checkpoint: a file it records that is gone or shorter, or a length that is
// not a byte count, is refused naming the checkpoint.
TEST_F(Dataset, ResumeChecksTheCheckpointAgainstItsFiles) {
  {
    DatasetWriter w(root_, DatasetLayout(0), kRun, {});
    w.appendFile("sequences/00/imu.csv").write("header\nrow1\n");
    w.checkpoint(5, {{"imu", 1}});
  }
  const fs::path imu = root_ / "sequences/00/imu.csv";
  const auto refused = [&](const std::string& why) {
    try {
      DatasetWriter(root_, DatasetLayout(0), kRun, {.resume = true});
      ADD_FAILURE() << "resumed despite " << why;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find((root_ / ".trainsim/checkpoint.json").string()),
                std::string::npos)
          << e.what();
    }
  };
  fs::resize_file(imu, 4);
  refused("a shortened file");
  fs::remove(imu);
  refused("a deleted file");
}

}  // namespace
}  // namespace trainsim::io
