#include "tools/output/output_folder.h"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

namespace csim {
namespace {

namespace fs = std::filesystem;

fs::path fresh_directory(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::set<std::string> entries(const fs::path& folder) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) names.insert(entry.path().filename().string());
  return names;
}

void write(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

TEST(OutputFolder, CommitReplacesTheFolderWholeAndLeavesNothingBeside) {
  const fs::path parent = fresh_directory("csim_output_folder_commit"), out = parent / "out";
  fs::create_directories(out / "paraview");
  write(out / "summary.json", "old");
  write(out / "work_precision.csv", "old");
  write(out / "paraview" / "bar_000099.vtu", "old");
  OutputFolder folder(out.string());
  EXPECT_EQ(fs::path(folder.path()).parent_path(), fs::weakly_canonical(parent));  // one filesystem: a rename
  write(fs::path(folder.path()) / "summary.json", "new");
  folder.commit();
  EXPECT_EQ(entries(out), std::set<std::string>{"summary.json"});
  std::ifstream summary(out / "summary.json");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(summary), {}), "new");
  EXPECT_EQ(entries(parent), std::set<std::string>{"out"});  // no temporary, old or lock file
}

TEST(OutputFolder, WithoutCommitTheDestinationStaysAsItWas) {
  const fs::path parent = fresh_directory("csim_output_folder_abandon"), out = parent / "out";
  fs::create_directories(out);
  write(out / "summary.json", "old");
  {
    OutputFolder folder(out.string());
    write(fs::path(folder.path()) / "summary.json", "new");
  }  // as when the command stops
  EXPECT_EQ(entries(parent), std::set<std::string>{"out"});
  std::ifstream summary(out / "summary.json");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(summary), {}), "old");
}

TEST(OutputFolder, ANewDestinationIsCreatedWithItsParents) {
  const fs::path parent = fresh_directory("csim_output_folder_new"), out = parent / "a" / "b";
  OutputFolder folder(out.string());
  folder.commit();
  EXPECT_TRUE(fs::is_directory(out));
  EXPECT_TRUE(fs::is_empty(out));
}

TEST(OutputFolder, AFolderHoldingTheUsersFilesIsRefusedUntouched) {
  const fs::path parent = fresh_directory("csim_output_folder_foreign"), out = parent / "out";
  fs::create_directories(out / "paraview");
  write(out / "paraview" / "notes.txt", "mine");
  try {
    OutputFolder folder(out.string());
    FAIL() << "a folder holding paraview/notes.txt was accepted";
  } catch (const OutputFolderError& e) {
    EXPECT_NE(std::string(e.what()).find("holds paraview/notes.txt, which csim did not write"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(entries(parent), std::set<std::string>{"out"});
  EXPECT_TRUE(fs::exists(out / "paraview" / "notes.txt"));
}

// A sweep's case folders hold what a run writes; anything else in them, or a case folder nested in
// another, is the user's.
TEST(OutputFolder, ASweepsCaseFoldersAreOursButNotWhatTheUserPutInThem) {
  const fs::path parent = fresh_directory("csim_output_folder_cases"), out = parent / "out";
  fs::create_directories(out / "case-0001" / "paraview");
  write(out / "sweep.csv", "case\n");
  write(out / "case-0001" / "summary.json", "{}");
  write(out / "case-0001" / "paraview" / "bar.pvd", "");
  {
    OutputFolder folder(out.string());
    write(fs::path(folder.path()) / "sweep.csv", "case\n");
    folder.commit();
  }
  EXPECT_EQ(entries(out), std::set<std::string>{"sweep.csv"});
  for (const char* foreign : {"case-0002/notes.txt", "case-0003/case-0001/summary.json", "case-x/summary.json"}) {
    fs::create_directories((out / foreign).parent_path());
    write(out / foreign, "mine");
    EXPECT_THROW(OutputFolder folder(out.string()), OutputFolderError) << foreign;
    fs::remove_all(out / fs::path(foreign).begin()->string());
  }
}

TEST(OutputFolder, FilesOfTheUsersAddedDuringTheRunStopTheSwap) {
  const fs::path parent = fresh_directory("csim_output_folder_late"), out = parent / "out";
  OutputFolder folder(out.string());
  fs::create_directories(out);
  write(out / "notes.txt", "mine");
  EXPECT_THROW(folder.commit(), OutputFolderError);
  EXPECT_TRUE(fs::exists(out / "notes.txt"));
}

// The id of a process that has ended and been reaped: no process has it (until the system reuses it).
pid_t dead_process_id() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ::waitpid(child, nullptr, 0);
  return child;
}

TEST(OutputFolder, TheFoldersOfDeadProcessesBesideTheDestinationAreRemoved) {
  const fs::path parent = fresh_directory("csim_output_folder_stale"), out = parent / "out";
  fs::create_directories(out);
  const std::string dead = std::to_string(dead_process_id()), live = std::to_string(::getppid());
  ASSERT_EQ(::kill(std::stoi(dead), 0), -1);  // the premise: no such process
  const std::set<std::string> removed = {".out.tmp-" + dead, ".out.old-" + dead};
  const std::set<std::string> kept = {".out.tmp-" + live,  ".out.old-" + live,  ".out.tmp-0" + dead,
                                      ".out.tmp-" + dead + "x", ".out.tmp--" + dead, ".other.tmp-" + dead,
                                      ".out.lock-" + dead, "out.tmp-" + dead};
  for (const std::set<std::string>* names : {&removed, &kept})
    for (const std::string& name : *names) {
      fs::create_directories(parent / name / "paraview");  // as a killed run leaves it
      write(parent / name / "paraview" / "bar_000000.vtu", "frame");
    }
  write(parent / (".out.tmp-" + dead + ".txt"), "a file, not a folder");
  OutputFolder folder(out.string());
  folder.commit();
  std::set<std::string> expected = kept;
  expected.insert({"out", ".out.tmp-" + dead + ".txt"});
  EXPECT_EQ(entries(parent), expected);
}

TEST(OutputFolder, AnOldFolderBesideAMissingDestinationIsKept) {
  // A process killed inside its swap, between moving the earlier outputs aside and moving its own in:
  // the old folder holds the only copy of the earlier outputs.
  const fs::path parent = fresh_directory("csim_output_folder_swap_cut"), out = parent / "out";
  const std::string dead = std::to_string(dead_process_id());
  fs::create_directories(parent / (".out.old-" + dead));
  fs::create_directories(parent / (".out.tmp-" + dead));
  OutputFolder folder(out.string());
  EXPECT_EQ(entries(parent), (std::set<std::string>{".out.old-" + dead, fs::path(folder.path()).filename().string()}));
}

}  // namespace
}  // namespace csim
