// A one-line progress bar on stderr for long runs (simulate, bench): the bar, the
// percentage, the elapsed time and the estimated time left, then a short detail.
// Each redraw returns to the start of the line and clears it first (ESC [K), and
// the line is cut to the terminal's width, so no stale characters stay behind. It
// appears only when stderr is a terminal and the run has taken more than a second.
#pragma once

#include <chrono>
#include <string>

namespace mbd {

// The text of one redraw (without the leading "\r\033[K"), at most `width` columns:
// "[=====>    ]  45%  0:12 elapsed, 0:15 left  t = 0.45 / 1 s".
std::string progress_line(double fraction, double elapsed_seconds, const std::string& detail, int width);

// "0:07", "1:02:03"; "--:--" for a time that is not finite.
std::string format_duration(double seconds);

class ProgressBar {
public:
    explicit ProgressBar(bool enabled);
    ~ProgressBar();
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;

    // fraction in [0, 1]; redrawn at most ten times a second.
    void update(double fraction, const std::string& detail);
    // Whether update() would redraw now: a caller with a costly detail builds it only then.
    bool due() const;
    // Clear the line (before a message or the summary).
    void finish();

private:
    bool enabled_;
    bool shown_ = false;
    std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace mbd
