#include "vkgi/progress.hpp"

#include <algorithm>
#include <cstdio>

#include <unistd.h>

namespace vkgi {

Progress::Progress(std::string label, uint64_t total, bool enabled)
    : m_label(std::move(label)), m_total(std::max<uint64_t>(total, 1)), m_visible(enabled && ::isatty(STDERR_FILENO)),
      m_start(std::chrono::steady_clock::now()), m_lastDraw(m_start) {}

Progress::~Progress() { finish(); }

void Progress::add(uint64_t done) {
    std::lock_guard lock(m_mutex);
    m_done = std::min(m_total, m_done + done);
    auto now = std::chrono::steady_clock::now();
    if (m_visible && now - m_lastDraw > std::chrono::milliseconds(100)) {
        m_lastDraw = now;
        draw(false);
    }
}

void Progress::note(const std::string& line) {
    std::lock_guard lock(m_mutex);
    if (m_visible && !m_finished)
        std::fputs("\r\033[K", stderr); // carriage return, erase the bar's line
    std::fprintf(stderr, "%s\n", line.c_str());
    if (m_visible && !m_finished)
        draw(false);
}

void Progress::finish() {
    std::lock_guard lock(m_mutex);
    if (m_finished)
        return;
    m_finished = true;
    if (m_visible)
        draw(true);
}

void Progress::draw(bool final) {
    constexpr int kWidth = 30; // bar characters: fits an 80-column terminal with the label and times
    double f = double(m_done) / double(m_total);
    double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    char bar[kWidth + 1];
    for (int i = 0; i < kWidth; ++i)
        bar[i] = i < int(f * kWidth) ? '#' : '.';
    bar[kWidth] = 0;
    std::string eta = f > 0.0 ? formatDuration(elapsed * (1.0 - f) / f) : "?";
    std::fprintf(stderr, "\r%s [%s] %5.1f%%  %s elapsed, ETA %s   ", m_label.c_str(), bar, 100.0 * f,
                 formatDuration(elapsed).c_str(), final ? "0 s" : eta.c_str());
    if (final)
        std::fputc('\n', stderr);
    std::fflush(stderr);
}

std::string formatDuration(double s) {
    char buf[32];
    if (s < 60.0)
        std::snprintf(buf, sizeof buf, "%.0f s", s);
    else if (s < 3600.0)
        std::snprintf(buf, sizeof buf, "%d min %02d s", int(s) / 60, int(s) % 60);
    else
        std::snprintf(buf, sizeof buf, "%d h %02d min", int(s) / 3600, (int(s) % 3600) / 60);
    return buf;
}

} // namespace vkgi
