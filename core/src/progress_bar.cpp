// The progress bar (see progress_bar.hpp).
#include <mbd/progress_bar.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sys/ioctl.h>
#include <unistd.h>

namespace mbd {

namespace {

int terminal_width() {
    struct winsize size {};
    if (::ioctl(::fileno(stderr), TIOCGWINSZ, &size) == 0 && size.ws_col > 0) return size.ws_col;
    return 80;
}

}  // namespace

std::string format_duration(double seconds) {
    if (!std::isfinite(seconds) || seconds < 0.0) return "--:--";
    const long s = std::lround(seconds);
    char text[32];
    if (s >= 3600)
        std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
    else
        std::snprintf(text, sizeof text, "%ld:%02ld", s / 60, s % 60);
    return text;
}

std::string progress_line(double fraction, double elapsed_seconds, const std::string& detail, int width) {
    fraction = std::clamp(std::isfinite(fraction) ? fraction : 0.0, 0.0, 1.0);
    const int bar_width = 30, filled = static_cast<int>(fraction * bar_width);
    std::string bar(filled, '=');
    if (filled < bar_width) bar += '>' + std::string(bar_width - filled - 1, ' ');
    // the time left at the mean rate so far
    const double left = fraction > 0.0 ? elapsed_seconds * (1.0 - fraction) / fraction : NAN;
    char head[160];
    std::snprintf(head, sizeof head, "[%s] %3d%%  %s elapsed, %s left", bar.c_str(),
                  static_cast<int>(100.0 * fraction), format_duration(elapsed_seconds).c_str(),
                  format_duration(left).c_str());
    std::string line = head;
    if (!detail.empty()) line += "  " + detail;
    // one column fewer than the terminal: a full line would wrap on some terminals
    const size_t limit = static_cast<size_t>(std::max(1, width - 1));
    if (line.size() > limit) line.resize(limit);
    return line;
}

ProgressBar::ProgressBar(bool enabled)
    : enabled_(enabled && ::isatty(::fileno(stderr))), start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() { finish(); }

bool ProgressBar::due() const {
    if (!enabled_) return false;
    const auto now = std::chrono::steady_clock::now();
    return now - start_ >= std::chrono::seconds(1) && !(shown_ && now - last_ < std::chrono::milliseconds(100));
}

void ProgressBar::update(double fraction, const std::string& detail) {
    if (!due()) return;
    const auto now = std::chrono::steady_clock::now();
    last_ = now;
    shown_ = true;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    std::fprintf(stderr, "\r\033[K%s", progress_line(fraction, elapsed, detail, terminal_width()).c_str());
    std::fflush(stderr);
}

void ProgressBar::finish() {
    if (!shown_) return;
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
    shown_ = false;
}

}  // namespace mbd
