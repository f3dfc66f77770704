#pragma once
// Progress with an ETA for long work (reference renders, sweeps): a one-line bar redrawn on
// stderr when stderr is a terminal, nothing at all when it is piped or redirected.
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace vkgi {

class Progress {
public:
    // `enabled` = false silences it even on a terminal (e.g. --quiet).
    Progress(std::string label, uint64_t total, bool enabled = true);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    // Thread-safe; redraws are rate-limited so a fast loop does not flood the terminal.
    void add(uint64_t done);
    void finish();
    // Prints one line on stderr without breaking the bar (it is redrawn below the line).
    void note(const std::string& line);
    bool visible() const { return m_visible; }

private:
    void draw(bool final);
    std::string m_label;
    uint64_t m_total;
    uint64_t m_done = 0;
    bool m_visible;
    bool m_finished = false;
    std::chrono::steady_clock::time_point m_start, m_lastDraw;
    std::mutex m_mutex;
};

// Formats seconds as "42 s", "3 min 05 s" or "1 h 02 min".
std::string formatDuration(double seconds);

} // namespace vkgi
