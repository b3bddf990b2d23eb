#include "tools/output/output_folder.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <system_error>

namespace csim {

namespace {

namespace fs = std::filesystem;

// Every file a csim command writes in its output folder (run: summary.json, probes.csv, bodies.csv, paraview/;
// compare: work_precision.*; stress: stability.*; sweep: sweep.csv, and each case's run outputs in a folder
// case-NNNN). A writer of a new file adds its name here, or the next
// command into that folder refuses the file as the user's.
const char* const kOwnFiles[] = {"summary.json",       "probes.csv",   "bodies.csv",   "work_precision.csv", "work_precision.gp",
                                 "work_precision.png", "stability.md", "stability.csv",
                                 "sweep.csv"};
const char* const kOwnFolder = "paraview";
const char* const kOwnFolderExtensions[] = {".vtu", ".vtp", ".pvd"};

bool own_file(const fs::directory_entry& entry, const char* const* first, const char* const* last, bool by_extension) {
  std::error_code error;
  if (entry.is_symlink(error) || !entry.is_regular_file(error)) return false;
  const fs::path& path = entry.path();
  if (path.extension() == ".tmp") return true;  // write_file_atomically's, from a run that was killed
  const std::string key = by_extension ? path.extension().string() : path.filename().string();
  return std::find_if(first, last, [&](const char* name) { return key == name; }) != last;
}

// The paraview/ folder holds only frames and collections, checked by extension.
std::string foreign_paraview_entry(const fs::path& folder, const std::string& destination) {
  std::error_code error;
  fs::directory_iterator entries(folder, error);
  for (; !error && entries != fs::directory_iterator(); entries.increment(error))
    if (!own_file(*entries, std::begin(kOwnFolderExtensions), std::end(kOwnFolderExtensions), true))
      return entries->path().filename().string();
  if (error) throw OutputFolderError(destination + ": cannot read the folder (" + error.message() + ")");
  return "";
}

// A case folder of `csim sweep`: case- and digits.
bool case_folder(const std::string& name) {
  return name.size() > 5 && name.rfind("case-", 0) == 0 &&
         std::all_of(name.begin() + 5, name.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// What in `folder` a csim command did not write: its top level by name, paraview/ by extension, a sweep's
// case folders as the folder of a run.
std::string first_foreign_entry(const fs::path& folder, const std::string& destination, bool top = true) {
  std::error_code error;
  fs::directory_iterator entries(folder, error);
  for (; !error && entries != fs::directory_iterator(); entries.increment(error)) {
    const fs::directory_entry& entry = *entries;
    if (own_file(entry, std::begin(kOwnFiles), std::end(kOwnFiles), false)) continue;
    const std::string name = entry.path().filename().string();
    const bool folder_of_ours = name == kOwnFolder || (top && case_folder(name));
    if (!folder_of_ours || entry.is_symlink(error) || !entry.is_directory(error)) return name;
    const std::string inside = name == kOwnFolder ? foreign_paraview_entry(entry.path(), destination)
                                                  : first_foreign_entry(entry.path(), destination, false);
    if (!inside.empty()) return name + "/" + inside;
  }
  if (error) throw OutputFolderError(destination + ": cannot read the folder (" + error.message() + ")");
  return "";
}

// Refuses a destination whose old content a swap may not replace.
void check_replaceable(const fs::path& target, const std::string& destination) {
  std::error_code error;
  const fs::file_status status = fs::symlink_status(target, error);
  if (!fs::exists(status)) return;
  if (!fs::is_directory(status)) throw OutputFolderError(destination + ": exists and is not a folder");
  const std::string foreign = first_foreign_entry(target, destination);
  if (!foreign.empty())
    throw OutputFolderError(destination + ": holds " + foreign +
                            ", which csim did not write; a command replaces its output folder whole, so name a new "
                            "folder, an empty one or one that csim wrote");
}

std::string message_of(int error_number) { return std::strerror(error_number); }

// An exclusive flock on a file beside the destination, held for a swap; the file is removed when the lock
// is released, so that nothing is left beside the destination. A waiter may thus lock a file that its
// holder has just unlinked: it checks after locking that the path still names the file it holds, and
// starts again if not.
class SwapLock {
 public:
  SwapLock(const fs::path& path, const std::string& destination) : path_(path) {
    while (true) {
      descriptor_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
      if (descriptor_ < 0)
        throw OutputFolderError(destination + ": cannot create the lock file " + path.string() + " (" +
                                message_of(errno) + ")");
      int locked;
      do locked = ::flock(descriptor_, LOCK_EX);
      while (locked != 0 && errno == EINTR);  // a signal that only sets a flag: wait on
      struct stat held, named;
      if (locked == 0 && ::fstat(descriptor_, &held) == 0 && ::stat(path.c_str(), &named) == 0 &&
          held.st_dev == named.st_dev && held.st_ino == named.st_ino)
        return;
      const int failure = locked != 0 ? errno : 0;
      ::close(descriptor_);
      if (failure != 0)
        throw OutputFolderError(destination + ": cannot lock " + path.string() + " (" + message_of(failure) + ")");
    }
  }
  ~SwapLock() {
    ::unlink(path_.c_str());  // before the release: a waiter then sees that its file is gone
    ::close(descriptor_);
  }
  SwapLock(const SwapLock&) = delete;
  SwapLock& operator=(const SwapLock&) = delete;

 private:
  fs::path path_;
  int descriptor_ = -1;
};

// `.NAME.SUFFIX` beside the destination.
fs::path beside(const fs::path& target, const std::string& suffix) {
  return target.parent_path() / ("." + target.filename().string() + "." + suffix);
}

std::string with_pid(const std::string& what) { return what + "-" + std::to_string(::getpid()); }

// The process id in `name` when it is exactly `.NAME.tmp-PID` or `.NAME.old-PID` of `target` (PID in
// decimal, no sign, no leading zero), else 0.
pid_t folder_owner(const std::string& name, const fs::path& target) {
  const std::string stem = "." + target.filename().string() + ".";
  if (name.size() <= stem.size() + 4 || name.compare(0, stem.size(), stem) != 0) return 0;
  const std::string kind = name.substr(stem.size(), 4);
  if (kind != "tmp-" && kind != "old-") return 0;
  const std::string digits = name.substr(stem.size() + 4);
  if (digits.size() > 9 || digits[0] == '0' ||
      !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return 0;  // 9 digits: every pid_t there is (Linux: at most 2^22)
  return static_cast<pid_t>(std::stoi(digits));
}

// Removes the temporary and old folders beside `target` that a process killed without a chance to clean
// up left there (SIGKILL, a crash, a power cut): those whose process no longer exists. A live process's
// folder (or one of a process of another user: kill() then says EPERM) is never touched; nor is anything
// not named exactly as OutputFolder names its folders for this destination. An old folder goes only when
// the destination exists: without it, the process was killed inside its swap and the old folder holds
// the only copy of the earlier outputs. kill() sees the processes of this machine only: a destination
// on a filesystem shared with other machines must not be written by commands on two of them at once
// (one would take the other's folder for a dead process's).
void remove_stale_folders(const fs::path& target) {
  std::error_code unknown, error;
  const bool has_destination = fs::exists(fs::symlink_status(target, unknown));
  fs::directory_iterator entries(target.parent_path(), error);
  for (; !error && entries != fs::directory_iterator(); entries.increment(error)) {
    const std::string name = entries->path().filename().string();
    const pid_t owner = folder_owner(name, target);
    std::error_code ignored;  // litter that cannot be removed is left, as before
    if (owner == 0 || owner == ::getpid() || entries->is_symlink(ignored) || !entries->is_directory(ignored))
      continue;
    const bool old_folder = name.compare(1 + target.filename().string().size(), 5, ".old-") == 0;
    if (old_folder && !has_destination) continue;
    if (::kill(owner, 0) == -1 && errno == ESRCH) fs::remove_all(entries->path(), ignored);
  }
}

}  // namespace

OutputFolder::OutputFolder(const std::string& destination) : destination_(destination) {
  std::error_code error;
  // Resolved through links (the folder a link names is the one replaced) and against the current folder,
  // which the destination must not hold: renaming it away would pull the ground from under the caller.
  fs::path target = fs::weakly_canonical(fs::absolute(destination, error), error);
  if (error || destination.empty()) throw OutputFolderError("'" + destination + "': not a folder name");
  if (!target.has_filename()) target = target.parent_path();  // "out/run/"
  const fs::path here = fs::weakly_canonical(fs::current_path(error), error);
  if (!error && std::mismatch(target.begin(), target.end(), here.begin(), here.end()).first == target.end())
    throw OutputFolderError(destination + ": is the current folder or holds it; name a folder of its own");
  check_replaceable(target, destination);
  fs::create_directories(target.parent_path(), error);
  if (error)
    throw OutputFolderError(destination + ": cannot create the folder " + target.parent_path().string() + " (" +
                            error.message() + ")");
  remove_stale_folders(target);
  const fs::path temporary = beside(target, with_pid("tmp"));
  fs::remove_all(temporary, error);  // of a killed process that had our process id: no one's now
  if (!fs::create_directory(temporary, error) || error)
    throw OutputFolderError(destination + ": cannot write beside it: cannot create " + temporary.string() + " (" +
                            (error ? error.message() : "it exists") + ")");
  target_ = target.string();
  temporary_ = temporary.string();
}

OutputFolder::~OutputFolder() {
  if (committed_) return;
  std::error_code ignored;  // a destructor must not throw; what cannot be removed stays
  fs::remove_all(temporary_, ignored);
}

void OutputFolder::commit() {
  const fs::path target(target_);
  const SwapLock lock(beside(target, "lock"), destination_);
  check_replaceable(target, destination_);  // again: the user may have put files there meanwhile
  std::error_code error;
  const bool had_old = fs::exists(fs::symlink_status(target, error));
  const fs::path old = beside(target, with_pid("old"));
  if (had_old) {
    fs::remove_all(old, error);
    fs::rename(target, old, error);
    if (error)
      throw OutputFolderError(destination_ + ": cannot move the earlier outputs aside (" + error.message() + ")");
  }
  fs::rename(temporary_, target, error);
  if (error) {
    std::error_code ignored;
    if (had_old) fs::rename(old, target, ignored);
    throw OutputFolderError(destination_ + ": cannot move the new outputs into place (" + error.message() + ")");
  }
  committed_ = true;
  // The swap is done: an old folder that cannot be removed is litter, not a failure of the command.
  if (had_old) fs::remove_all(old, error);
}

}  // namespace csim
