// Messages a plugin addresses to the user while it works: the path it chose, the
// redundant constraint rows it left out, a re-selection of coordinates. The host
// decides where they go (`mbd simulate -q` drops them), so a plugin writes them
// through the MessageLog it is given (FormulationOptions::log), never to
// std::cout or std::clog directly.
#pragma once

#include <functional>
#include <iostream>
#include <string>
#include <utility>

namespace mbd {

class MessageLog {
public:
    using Sink = std::function<void(const std::string& line)>;

    // One line per message on std::clog (the default of a library user).
    MessageLog() : sink_([](const std::string& line) { std::clog << line << '\n'; }) {}
    // An empty sink drops every message.
    explicit MessageLog(Sink sink) : sink_(std::move(sink)) {}
    static MessageLog silent() { return MessageLog(Sink()); }

    bool enabled() const { return static_cast<bool>(sink_); }
    void operator()(const std::string& line) const {
        if (sink_) sink_(line);
    }

private:
    Sink sink_;
};

}  // namespace mbd
