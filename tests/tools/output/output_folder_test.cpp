#include "tools/output/output_folder.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace csim
