// The file is written through a descriptor of its own (not std::ofstream) so that the reason of the first
// failed write(2), fsync-less close(2) or rename(2) is kept as errno gave it: a stream only says that it
// failed, and errno may have changed by the time it says so.
#include "tools/output/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <ostream>
#include <streambuf>
#include <vector>

namespace csim {

namespace {

// An output buffer over a file descriptor that remembers the errno of its first failed write.
class DescriptorBuffer : public std::streambuf {
 public:
  explicit DescriptorBuffer(int descriptor) : descriptor_(descriptor), buffer_(1 << 16) {
    setp(buffer_.data(), buffer_.data() + buffer_.size());
  }
  int error() const { return error_; }

 protected:
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  // Writes what the buffer holds; false (errno kept) when write(2) fails.
  bool drain() {
    if (error_ != 0) return false;
    const char* data = pbase();
    std::size_t left = static_cast<std::size_t>(pptr() - pbase());
    while (left > 0) {
      const ssize_t written = ::write(descriptor_, data, left);
      if (written < 0 && errno == EINTR) continue;  // a stop signal, which only sets a flag
      if (written <= 0) {
        error_ = written < 0 ? errno : EIO;
        return false;
      }
      data += written;
      left -= static_cast<std::size_t>(written);
    }
    setp(buffer_.data(), buffer_.data() + buffer_.size());
    return true;
  }

  int descriptor_;
  std::vector<char> buffer_;
  int error_ = 0;
};

std::error_code reason(int error_number) { return {error_number, std::generic_category()}; }

}  // namespace

FileWriteError FileWriteError::in_folder(const std::string& written, const std::string& shown) const {
  if (written.empty() || path.compare(0, written.size(), written) != 0 ||
      (path.size() > written.size() && path[written.size()] != '/'))
    return *this;
  return FileWriteError(shown + path.substr(written.size()), failure, code());
}

void write_file_atomically(const std::string& path, const std::string& contents) {
  write_file_atomically(path, [&contents](std::ostream& out) { out << contents; });
}

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const std::string temporary = path + ".tmp";
  const int descriptor = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (descriptor < 0) throw FileWriteError(path, "cannot open for writing", reason(errno));
  int failure = 0;
  {
    DescriptorBuffer buffer(descriptor);
    std::ostream out(&buffer);
    try {
      write(out);
    } catch (...) {
      ::close(descriptor);
      std::remove(temporary.c_str());
      throw;
    }
    out.flush();
    failure = buffer.error();
    if (failure == 0 && !out) failure = EIO;  // the stream failed without a failed write(2)
  }
  // close(2) may report what a delayed write met (NFS, quotas): it counts as the write's failure.
  if (::close(descriptor) != 0 && failure == 0 && errno != EINTR) failure = errno;  // EINTR: closed all the same
  if (failure != 0) {
    std::remove(temporary.c_str());
    throw FileWriteError(path, "cannot write", reason(failure));
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const int error = errno;
    std::remove(temporary.c_str());
    throw FileWriteError(path, "cannot rename the finished file into place", reason(error));
  }
}

}  // namespace csim
