// An exclusive lock on a result file for the length of a run: flock(2) on OUTPUT.lock beside
// it, so that two runs writing the same output cannot both go on and lose one's results. The
// second is refused at its start with the holder's description (program, process id, host,
// start time), which the holder writes into the lock file. The kernel releases the lock when
// its holder ends however it ends (a kill included): a lock file left behind by a killed run
// blocks nothing. The holder removes the file when done; a run that opened it in that moment
// sees that its lock is on a removed file and takes a new one.
#pragma once

#include <filesystem>
#include <string>

namespace mbd {

class OutputLock {
public:
    // Locks OUTPUT.lock for `holder` (e.g. "mbd sweep"); InputError naming `option` and the
    // other holder when another run has it, OutputError when the lock file cannot be made.
    OutputLock(const std::filesystem::path& output, const std::string& option, const std::string& holder);
    ~OutputLock();  // removes OUTPUT.lock, then releases the lock
    OutputLock(const OutputLock&) = delete;
    OutputLock& operator=(const OutputLock&) = delete;

    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
    int fd_ = -1;
};

}  // namespace mbd
