// An output folder that is replaced whole when a command ends, or left as it was (docs/contract.md "Outputs
// in DIR"). A command writes into a temporary folder beside the destination, `.NAME.tmp-PID` in the same
// parent (so that one rename moves it, on one filesystem), and commit() swaps it in under an exclusive
// flock on `.NAME.lock` beside it: the old folder is renamed to `.NAME.old-PID`, the temporary one to
// NAME, and the old one removed. Two commands writing to one destination each have their own temporary
// folder; the last to commit wins and the folder never holds a mix of the two. Destroyed without commit()
// (an error, a stop request), it removes its temporary folder: the destination stays as it was. A
// process killed outright (SIGKILL, a crash) cannot: the next OutputFolder for the same destination
// removes the `.NAME.tmp-PID` and `.NAME.old-PID` folders beside it whose process no longer exists.
//
// Since the destination is replaced whole, it may hold only what csim commands write (their file names
// are listed in output_folder.cpp): a folder with anything else in it is refused, before any work, so
// that an --out naming a folder of the user's never deletes it.
#pragma once

#include <stdexcept>
#include <string>

namespace csim {

// A destination that cannot be used, or a swap that failed: the message names the destination.
struct OutputFolderError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class OutputFolder {
 public:
  // Creates the temporary folder, and the destination's parent when missing, after removing the folders
  // of dead processes beside the destination (see above). Throws OutputFolderError
  // when it cannot (the folder is not writable), when the destination is not a folder, holds the current
  // folder or holds files csim did not write.
  explicit OutputFolder(const std::string& destination);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  // Where the command writes: the temporary folder.
  const std::string& path() const { return temporary_; }

  // Swaps the temporary folder in (see above). Throws OutputFolderError when a rename fails, the
  // destination then restored, or when files csim did not write appeared in the destination meanwhile.
  void commit();

 private:
  std::string destination_;  // as the user named it, for messages
  std::string target_;       // the folder replaced: destination_, or what it links to
  std::string temporary_;
  bool committed_ = false;
};

}  // namespace csim
