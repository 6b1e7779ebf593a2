// A one-line progress bar on stderr for long runs (simulate, bench, sweep, stability): the
// bar, the percentage, the elapsed time and the estimated time left, then a short detail.
//
// The bar owns the terminal's last line while it is shown. Every other line meant for the
// terminal goes above it: console_line() (and, while a bar is shown, anything written to
// std::cerr or std::clog, one whole line at a time) clears the bar's line, prints the
// message with its newline and redraws the bar below it, so no message ever lands on the
// bar's line. Each redraw returns to the start of the line and clears it first (ESC [K),
// and the line is cut to the terminal's width (terminal_width()), so it never wraps. The
// bar appears only when stderr is a terminal and the run has taken more than a second; one
// bar at a time owns the line (a bar made while another is shown stays hidden).
#pragma once

#include <chrono>
#include <cstdio>
#include <streambuf>
#include <string>

namespace mbd {

// The text of one redraw (without the leading "\r\033[K"), at most `width` - 1 columns:
// "[=====>    ]  45%  0:12 elapsed, 0:15 left  t = 0.45 / 1 s".
std::string progress_line(double fraction, double elapsed_seconds, const std::string& detail, int width);

// "0:07", "1:02:03"; "--:--" for a time that is not finite.
std::string format_duration(double seconds);

// The terminal's width in columns: stderr's TIOCGWINSZ, else $COLUMNS, else 80.
int terminal_width();

// `text` cut to at most `columns` columns; a UTF-8 character counts one column and is never split.
std::string fit_to_width(const std::string& text, int columns);

// One line for the user (without its newline) on `stream` (stderr or stdout): above the
// progress bar when one is shown, else written straight away.
void console_line(const std::string& line, std::FILE* stream = stderr);

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
    // Clear the line (before the summary); the bar is drawn again by the next update().
    void finish();

private:
    friend void console_line(const std::string& line, std::FILE* stream);
    void draw() const;  // the console's lock held

    bool enabled_;
    bool shown_ = false;
    std::string line_;  // the bar's text as last drawn
    std::chrono::steady_clock::time_point start_, last_;
    std::streambuf* saved_cerr_ = nullptr;
    std::streambuf* saved_clog_ = nullptr;
};

}  // namespace mbd
