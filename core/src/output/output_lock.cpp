// The lock on a result file for the length of a run (output_lock.hpp).
#include <mbd/output_lock.hpp>

#include <mbd/output_file.hpp>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace mbd {

namespace {

std::string quoted(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

// "mbd sweep, process 1234 on host node7, since 2026-12-07 03:20:01 UTC"
std::string holder_text(const std::string& holder) {
    char host[256] = "";
    if (::gethostname(host, sizeof host - 1) != 0) host[0] = '\0';
    const std::time_t now = std::time(nullptr);
    std::tm utc{};
    gmtime_r(&now, &utc);
    char since[40];
    std::strftime(since, sizeof since, "%Y-%m-%d %H:%M:%S UTC", &utc);
    return holder + ", process " + std::to_string(::getpid()) + (host[0] ? std::string(" on host ") + host : "") +
           ", since " + since;
}

// What the holder wrote into the lock file (it may not have written it yet).
std::string read_holder(int fd) {
    char text[512];
    const ssize_t n = ::pread(fd, text, sizeof text - 1, 0);
    std::string out(text, n > 0 ? static_cast<std::size_t>(n) : 0);
    while (!out.empty() && (out.back() == '\n' || out.back() == '\0')) out.pop_back();
    return out;
}

// The open descriptor is the file now at `path` (not one its holder removed meanwhile).
bool still_linked(int fd, const std::filesystem::path& path) {
    struct stat opened {}, named {};
    return ::fstat(fd, &opened) == 0 && ::stat(path.c_str(), &named) == 0 && opened.st_dev == named.st_dev &&
           opened.st_ino == named.st_ino;
}

}  // namespace

OutputLock::OutputLock(const std::filesystem::path& output, const std::string& option, const std::string& holder)
    : path_(output.string() + ".lock") {
    for (;;) {
        const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
        if (fd < 0) throw OutputError(output, std::string(std::strerror(errno)) + " (creating the lock " + quoted(path_) + ")");
        if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
            const int error = errno;
            const std::string other = read_holder(fd);
            ::close(fd);
            if (error != EWOULDBLOCK)
                throw OutputError(output, std::string(std::strerror(error)) + " (locking " + quoted(path_) + ")");
            throw InputError(option, quoted(output) + " is being written by another run (" +
                                         (other.empty() ? std::string("its lock ") + quoted(path_) : other) +
                                         "); wait for it to end, or choose another output name");
        }
        if (!still_linked(fd, path_)) {  // its holder removed it as we opened it: take the new one
            ::close(fd);
            continue;
        }
        fd_ = fd;
        break;
    }
    const std::string text = holder_text(holder) + "\n";
    if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, text.data(), text.size(), 0) != static_cast<ssize_t>(text.size())) {
        const std::string why = std::strerror(errno);
        ::unlink(path_.c_str());
        ::close(fd_);
        throw OutputError(output, why + " (writing the lock " + quoted(path_) + ")");
    }
}

OutputLock::~OutputLock() {
    ::unlink(path_.c_str());  // while held: whoever opens it next finds it removed and makes a new one
    ::close(fd_);
}

}  // namespace mbd
