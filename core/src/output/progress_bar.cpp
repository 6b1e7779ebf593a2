// The progress bar and the terminal lines above it (see progress_bar.hpp).
#include <mbd/progress_bar.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <sys/ioctl.h>
#include <unistd.h>

namespace mbd {

namespace {

// std::cerr and std::clog while a bar is shown: each whole line goes to console_line(), so
// it lands above the bar; a partial line waits for its newline (one per thread, so the
// lines of two threads never mix).
class LineRouter : public std::streambuf {
public:
    static std::string& pending() {
        thread_local std::string text;
        return text;
    }

protected:
    int_type overflow(int_type c) override {
        if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
        put(traits_type::to_char_type(c));
        return c;
    }
    std::streamsize xsputn(const char* s, std::streamsize n) override {
        for (std::streamsize k = 0; k < n; ++k) put(s[k]);
        return n;
    }

private:
    static void put(char c) {
        std::string& text = pending();
        if (c != '\n') {
            text += c;
            return;
        }
        const std::string line = std::move(text);
        text.clear();
        console_line(line, stderr);
    }
};

// The terminal's last line: which bar owns it, and the lock every write to it takes.
struct Console {
    std::mutex mutex;
    const ProgressBar* owner = nullptr;
    LineRouter router;
};

Console& console() {
    static Console* the_console = new Console;  // never destroyed: a message at exit still finds it
    return *the_console;
}

constexpr const char* kClearLine = "\r\033[K";

}  // namespace

int terminal_width() {
    struct winsize size {};
    if (::ioctl(::fileno(stderr), TIOCGWINSZ, &size) == 0 && size.ws_col > 0) return size.ws_col;
    if (const char* columns = std::getenv("COLUMNS")) {
        const int n = std::atoi(columns);
        if (n > 0) return n;
    }
    return 80;
}

std::string fit_to_width(const std::string& text, int columns) {
    int used = 0;
    for (size_t k = 0; k < text.size(); ++k) {
        const bool starts_character = (static_cast<unsigned char>(text[k]) & 0xC0) != 0x80;
        if (starts_character && ++used > columns) return text.substr(0, k);
    }
    return text;
}

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
    // the time left at the mean rate so far
    const double left = fraction > 0.0 ? elapsed_seconds * (1.0 - fraction) / fraction : NAN;
    char times[96];
    std::snprintf(times, sizeof times, " %3d%%  %s elapsed, %s left", static_cast<int>(100.0 * fraction),
                  format_duration(elapsed_seconds).c_str(), format_duration(left).c_str());
    const std::string tail = detail.empty() ? std::string() : "  " + detail;
    // one column fewer than the terminal: a full line would wrap on some terminals
    const int columns = std::max(1, width - 1);
    // the bar gives up columns (30 down to 10) before the detail is cut
    const int room = columns - 2 - static_cast<int>(std::string(times).size() + fit_to_width(tail, columns).size());
    const int bar_width = std::clamp(room, 10, 30), filled = static_cast<int>(fraction * bar_width);
    std::string bar(filled, '=');
    if (filled < bar_width) bar += '>' + std::string(bar_width - filled - 1, ' ');
    return fit_to_width("[" + bar + "]" + times + tail, columns);
}

void console_line(const std::string& line, std::FILE* stream) {
    Console& c = console();
    std::lock_guard<std::mutex> lock(c.mutex);
    const ProgressBar* bar = c.owner && c.owner->shown_ ? c.owner : nullptr;
    if (bar) {
        std::fputs(kClearLine, stderr);
        std::fflush(stderr);
    }
    std::fwrite(line.data(), 1, line.size(), stream);
    std::fputc('\n', stream);
    std::fflush(stream);
    if (bar) bar->draw();
}

ProgressBar::ProgressBar(bool enabled)
    : enabled_(enabled && ::isatty(::fileno(stderr))), start_(std::chrono::steady_clock::now()) {
    if (!enabled_) return;
    Console& c = console();
    std::lock_guard<std::mutex> lock(c.mutex);
    if (c.owner) {  // another bar owns the line
        enabled_ = false;
        return;
    }
    c.owner = this;
    saved_cerr_ = std::cerr.rdbuf(&c.router);
    saved_clog_ = std::clog.rdbuf(&c.router);
}

ProgressBar::~ProgressBar() {
    finish();
    if (!enabled_) return;
    Console& c = console();
    std::lock_guard<std::mutex> lock(c.mutex);
    std::cerr.rdbuf(saved_cerr_);
    std::clog.rdbuf(saved_clog_);
    c.owner = nullptr;
    std::string& partial = LineRouter::pending();  // a line still waiting for its newline
    if (!partial.empty()) {
        std::fputs(partial.c_str(), stderr);
        std::fflush(stderr);
        partial.clear();
    }
}

bool ProgressBar::due() const {
    if (!enabled_) return false;
    const auto now = std::chrono::steady_clock::now();
    return now - start_ >= std::chrono::seconds(1) && !(shown_ && now - last_ < std::chrono::milliseconds(100));
}

void ProgressBar::update(double fraction, const std::string& detail) {
    if (!due()) return;
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    std::string line = progress_line(fraction, elapsed, detail, terminal_width());
    std::lock_guard<std::mutex> lock(console().mutex);
    last_ = now;
    shown_ = true;
    line_ = std::move(line);
    draw();
}

void ProgressBar::draw() const {
    std::fputs(kClearLine, stderr);
    std::fputs(line_.c_str(), stderr);
    std::fflush(stderr);
}

void ProgressBar::finish() {
    if (!shown_) return;
    std::lock_guard<std::mutex> lock(console().mutex);
    std::fputs(kClearLine, stderr);
    std::fflush(stderr);
    shown_ = false;
}

}  // namespace mbd
