#include "vkgi/bench.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>

#include "vkgi/vct.hpp"

#include <nlohmann/json.hpp>

namespace vkgi::gi {

std::vector<size_t> paretoFront(const std::vector<BenchRecord>& records, const std::string& scene) {
    std::vector<size_t> idx;
    for (size_t i = 0; i < records.size(); ++i)
        if (records[i].scene == scene && std::isfinite(records[i].totalMs) && std::isfinite(records[i].relMse))
            idx.push_back(i);
    std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) {
        const BenchRecord &ra = records[a], &rb = records[b];
        return ra.totalMs != rb.totalMs ? ra.totalMs < rb.totalMs : ra.relMse < rb.relMse;
    });
    // Sweep by time: a record is on the front when it is more accurate than everything faster.
    std::vector<size_t> front;
    double best = INFINITY;
    for (size_t i : idx)
        if (records[i].relMse < best) {
            front.push_back(i);
            best = records[i].relMse;
        }
    return front;
}

long bestWithinBudget(const std::vector<BenchRecord>& records, const std::string& scene, double budgetMs) {
    long best = -1;
    for (size_t i = 0; i < records.size(); ++i) {
        const BenchRecord& r = records[i];
        if (r.scene != scene || !(r.totalMs <= budgetMs) || !std::isfinite(r.relMse))
            continue;
        if (best < 0 || r.relMse < records[size_t(best)].relMse)
            best = long(i);
    }
    return best;
}

namespace {
std::string csvField(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos)
        return s;
    std::string out = "\"";
    for (char c : s)
        out += c == '"' ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
}
std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}
} // namespace

double streamRatio(double ms, double bytes, double streamGBs) {
    if (!(bytes > 0.0) || !(streamGBs > 0.0))
        return 0.0;
    return ms / (bytes / (streamGBs * 1e6));
}

std::string toCsv(const std::vector<BenchRecord>& records) {
    // Pass columns are the union of pass names over all records, in first-seen order.
    std::vector<std::string> passes;
    for (const auto& r : records)
        for (const auto& [name, ms] : r.passMs)
            if (std::find(passes.begin(), passes.end(), name) == passes.end())
                passes.push_back(name);
    std::ostringstream out;
    out << "scene,technique,knobs,total_ms,profiled_ms,relmse,rmse,relmse_indirect,rmse_indirect,reference_bounces,"
           "relmse_all,"
           "rmse_all,relmse_indirect_all,rmse_indirect_all,relmse_dark,relmse_all_dark,device_mib,direct_ms,hf_ratio";
    for (const auto& p : passes)
        out << "," << csvField(p + " ms");
    out << "\n";
    for (const auto& r : records) {
        out << csvField(r.scene) << "," << csvField(r.technique) << "," << csvField(r.knobs) << "," << num(r.totalMs)
            << "," << num(r.profiledMs) << "," << num(r.relMse) << "," << num(r.rmse) << "," << num(r.relMseIndirect)
            << "," << num(r.rmseIndirect) << "," << r.referenceBounces << "," << num(r.relMseAll) << ","
            << num(r.rmseAll) << "," << num(r.relMseIndirectAll) << "," << num(r.rmseIndirectAll) << ","
            << num(r.relMseDark) << "," << num(r.relMseAllDark) << "," << num(r.deviceMiB) << "," << num(r.directMs) << ","
            << num(r.hfRatio);
        for (const auto& p : passes) {
            auto it = std::find_if(r.passMs.begin(), r.passMs.end(), [&](const auto& e) { return e.first == p; });
            out << "," << (it == r.passMs.end() ? std::string() : num(it->second));
        }
        out << "\n";
    }
    return out.str();
}

std::string toJson(const std::vector<BenchRecord>& records) {
    nlohmann::json arr = nlohmann::json::array();
    for (const auto& r : records) {
        nlohmann::json passes = nlohmann::json::array();
        for (const auto& entry : r.passMs) {
            const auto& [name, ms] = entry;
            nlohmann::json pass = {{"name", name}, {"ms", ms}};
            auto it = std::find_if(r.passBytes.begin(), r.passBytes.end(),
                                   [&](const auto& e) { return e.first == entry.first; });
            if (it != r.passBytes.end()) {
                pass["bytes"] = it->second;
                pass["stream_ratio"] = streamRatio(ms, it->second, r.streamGBs);
            }
            passes.push_back(pass);
        }
        arr.push_back({{"scene", r.scene},
                       {"technique", r.technique},
                       {"knobs", r.knobs},
                       {"passes", passes},
                       {"total_ms", r.totalMs},
                       {"profiled_ms", r.profiledMs},
                       {"direct_ms", r.directMs},
                       {"device_mib", r.deviceMiB},
                       {"stream_gbs", r.streamGBs},
                       {"error",
                        {{"relmse", r.relMse},
                         {"rmse", r.rmse},
                         {"relmse_indirect", r.relMseIndirect},
                         {"rmse_indirect", r.rmseIndirect},
                         {"relmse_dark", r.relMseDark},
                         {"hf_ratio", r.hfRatio},
                         {"reference_bounces", r.referenceBounces}}},
                       {"error_all_bounces",
                        {{"relmse", r.relMseAll},
                         {"rmse", r.rmseAll},
                         {"relmse_indirect", r.relMseIndirectAll},
                         {"rmse_indirect", r.rmseIndirectAll},
                         {"relmse_dark", r.relMseAllDark}}}});
    }
    return arr.dump(2) + "\n";
}

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// "VCT voxelization (<T> triangles, ...): grid <G>: voxelize <ms> ms = <rate> M triangles/s,
// all voxel-grid passes <ms> ms; ..." (medians over the scene's VCT records), or "" without any.
std::string voxelizationLine(const std::vector<BenchRecord>& records, const std::string& scene) {
    std::map<uint32_t, std::vector<double>> voxelize, grid;
    uint64_t triangles = 0;
    for (const BenchRecord& r : records) {
        if (r.scene != scene || r.technique != "vct")
            continue;
        double v = 0.0, all = 0.0;
        bool found = false;
        for (const auto& [name, ms] : r.passMs) {
            if (name == "gi.voxel.voxelize") {
                v = ms;
                found = true;
            }
            if (name.rfind("gi.voxel.", 0) == 0 || name.rfind("gi.vct.list", 0) == 0)
                all += ms;
        }
        if (!found)
            continue;
        triangles = r.triangles;
        voxelize[vctGridOf(r)].push_back(v);
        grid[vctGridOf(r)].push_back(all);
    }
    if (voxelize.empty())
        return "";
    std::ostringstream out;
    char buf[160];
    out << "VCT voxelization (" << triangles << " triangles, re-voxelized every frame; medians over the VCT rows):";
    for (const auto& [n, times] : voxelize) {
        double ms = median(times);
        std::snprintf(buf, sizeof buf, " grid %u: voxelize %.3g ms = %.3g M triangles/s, all voxel-grid passes %.3g ms;", n,
                      ms, ms > 0.0 ? double(triangles) / (ms * 1e3) : 0.0, median(grid[n]));
        out << buf;
    }
    out << "\n\n";
    return out.str();
}

} // namespace

std::string toMarkdown(const std::vector<BenchRecord>& records) {
    std::vector<std::string> scenes;
    for (const auto& r : records)
        if (std::find(scenes.begin(), scenes.end(), r.scene) == scenes.end())
            scenes.push_back(r.scene);
    std::ostringstream out;
    auto g = [](double v) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.3g", v);
        return std::string(buf);
    };
    for (const auto& scene : scenes) {
        std::vector<size_t> front = paretoFront(records, scene);
        out << "### " << scene << "\n\n"
            << "| technique | knobs | GPU ms | × direct | MiB | ref. bounces | relMSE | relMSE (ε 1e-3) | relMSE ind. | "
               "RMSE ind. | HF ratio | all bounces: relMSE (ε 1e-3) | relMSE ind. | RMSE ind. |\n"
            << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
        for (size_t i = 0; i < records.size(); ++i) {
            const BenchRecord& r = records[i];
            if (r.scene != scene)
                continue;
            bool onFront = std::find(front.begin(), front.end(), i) != front.end();
            std::string knobs = r.knobs.empty() ? "(defaults)" : r.knobs;
            for (char& c : knobs)
                c = c == '|' ? '/' : c;
            out << "| " << r.technique << (onFront ? " *" : "") << " | " << knobs << " | " << g(r.totalMs) << " | "
                << (r.directMs > 0.0 ? g(r.totalMs / r.directMs) : std::string("–")) << " | " << g(r.deviceMiB) << " | " << (r.referenceBounces < 0 ? std::string("all") : std::to_string(r.referenceBounces))
                << " | " << g(r.relMse) << " | " << g(r.relMseDark) << " | " << g(r.relMseIndirect) << " | "
                << g(r.rmseIndirect) << " | " << g(r.hfRatio) << " | " << g(r.relMseAllDark) << " | " << g(r.relMseIndirectAll) << " | "
                << g(r.rmseIndirectAll) << " |\n";
        }
        out << "\n";
        out << voxelizationLine(records, scene);
    }
    return out.str();
}

uint32_t vctGridOf(const BenchRecord& record) {
    const std::string key = "vct.grid=";
    size_t at = record.knobs.find(key);
    if (at == std::string::npos)
        return VctSettings{}.gridResolution;
    return uint32_t(std::strtoul(record.knobs.c_str() + at + key.size(), nullptr, 10));
}

namespace {

struct Axis {
    double lo, hi; // log10 range
    double map(double v, double p0, double p1) const { return p0 + (std::log10(v) - lo) / (hi - lo) * (p1 - p0); }
};

Axis logAxis(double mn, double mx) {
    double lo = std::floor(std::log10(mn)), hi = std::ceil(std::log10(mx));
    if (hi <= lo)
        hi = lo + 1;
    return {lo, hi};
}

std::string escapeXml(const std::string& s) {
    std::string o;
    for (char c : s)
        o += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : std::string(1, c);
    return o;
}

const char* const kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};

// The log-log plots' canvas (legend on the right) and the mapping of values onto it.
struct PlotFrame {
    static constexpr double W = 640, H = 420, L = 70, R = 170, T = 40, B = 50;
    Axis ax, ay;
    double X(double v) const { return ax.map(v, L, W - R); }
    double Y(double v) const { return ay.map(v, H - B, T); }
};

void svgOpen(std::ostringstream& s, const std::string& title) {
    s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << PlotFrame::W << "\" height=\"" << PlotFrame::H
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    s << "<text x=\"" << PlotFrame::L << "\" y=\"24\" font-size=\"15\">" << escapeXml(title) << "</text>\n";
}

// Decade grid lines with their labels (y as 1eN when `yExponent`) and the axis titles.
void svgGrid(std::ostringstream& s, const PlotFrame& f, const std::string& xTitle, const std::string& yTitle,
             bool yExponent) {
    constexpr double W = PlotFrame::W, H = PlotFrame::H, L = PlotFrame::L, R = PlotFrame::R, T = PlotFrame::T,
                     B = PlotFrame::B;
    for (double d = f.ax.lo; d <= f.ax.hi; ++d)
        s << "<line x1=\"" << f.X(std::pow(10, d)) << "\" y1=\"" << T << "\" x2=\"" << f.X(std::pow(10, d))
          << "\" y2=\"" << H - B << "\" stroke=\"#ddd\"/><text x=\"" << f.X(std::pow(10, d)) << "\" y=\""
          << H - B + 16 << "\" text-anchor=\"middle\">" << num(std::pow(10, d)) << "</text>\n";
    for (double d = f.ay.lo; d <= f.ay.hi; ++d)
        s << "<line x1=\"" << L << "\" y1=\"" << f.Y(std::pow(10, d)) << "\" x2=\"" << W - R << "\" y2=\""
          << f.Y(std::pow(10, d)) << "\" stroke=\"#ddd\"/><text x=\"" << L - 6 << "\" y=\"" << f.Y(std::pow(10, d)) + 4
          << "\" text-anchor=\"end\">" << (yExponent ? "1e" + std::to_string(int(d)) : num(std::pow(10, d)))
          << "</text>\n";
    s << "<text x=\"" << (L + W - R) / 2 << "\" y=\"" << H - 12 << "\" text-anchor=\"middle\">" << escapeXml(xTitle)
      << "</text>\n";
    s << "<text x=\"16\" y=\"" << (T + H - B) / 2 << "\" transform=\"rotate(-90 16 " << (T + H - B) / 2
      << ")\" text-anchor=\"middle\">" << escapeXml(yTitle) << "</text>\n";
}

} // namespace

std::string toSvgPlot(const std::vector<BenchRecord>& records, const std::string& scene) {
    constexpr double W = PlotFrame::W, L = PlotFrame::L, R = PlotFrame::R, T = PlotFrame::T;
    std::vector<size_t> pts;
    double tMin = INFINITY, tMax = 0, eMin = INFINITY, eMax = 0;
    for (size_t i = 0; i < records.size(); ++i) {
        const auto& r = records[i];
        if (r.scene != scene || !(r.totalMs > 0) || !(r.relMse > 0) || !std::isfinite(r.relMse))
            continue;
        pts.push_back(i);
        tMin = std::min(tMin, r.totalMs), tMax = std::max(tMax, r.totalMs);
        eMin = std::min(eMin, r.relMse), eMax = std::max(eMax, r.relMse);
    }
    std::ostringstream s;
    svgOpen(s, scene + ": error against GPU time (log-log)");
    if (pts.empty())
        return s.str() + "<text x=\"" + num(L) + "\" y=\"80\">no finite measurements</text>\n</svg>\n";
    PlotFrame f{logAxis(tMin, tMax), logAxis(eMin, eMax)};
    auto X = [&](double v) { return f.X(v); };
    auto Y = [&](double v) { return f.Y(v); };
    svgGrid(s, f, "total GPU ms", "relMSE", true);
    std::map<std::string, const char*> colourOf;
    for (size_t i : pts)
        if (!colourOf.count(records[i].technique))
            colourOf[records[i].technique] = kColours[colourOf.size() % 6];
    auto front = paretoFront(records, scene);
    s << "<polyline fill=\"none\" stroke=\"black\" stroke-width=\"1.5\" stroke-dasharray=\"4 3\" points=\"";
    for (size_t i : front)
        s << X(records[i].totalMs) << "," << Y(records[i].relMse) << " ";
    s << "\"/>\n";
    std::set<size_t> onFront(front.begin(), front.end());
    for (size_t i : pts) {
        const auto& r = records[i];
        s << "<circle cx=\"" << X(r.totalMs) << "\" cy=\"" << Y(r.relMse) << "\" r=\"" << (onFront.count(i) ? 5 : 3.5)
          << "\" fill=\"" << colourOf[r.technique] << "\"" << (onFront.count(i) ? " stroke=\"black\"" : "")
          << "><title>" << escapeXml(r.technique + " " + r.knobs) << ": " << num(r.totalMs) << " ms, relMSE "
          << num(r.relMse) << "</title></circle>\n";
    }
    double ly = T + 10;
    for (const auto& [tech, colour] : colourOf) {
        s << "<circle cx=\"" << W - R + 20 << "\" cy=\"" << ly << "\" r=\"5\" fill=\"" << colour << "\"/><text x=\""
          << W - R + 32 << "\" y=\"" << ly + 4 << "\">" << escapeXml(tech) << "</text>\n";
        ly += 20;
    }
    s << "<line x1=\"" << W - R + 12 << "\" y1=\"" << ly << "\" x2=\"" << W - R + 28 << "\" y2=\"" << ly
      << "\" stroke=\"black\" stroke-dasharray=\"4 3\"/><text x=\"" << W - R + 32 << "\" y=\"" << ly + 4
      << "\">Pareto front</text>\n</svg>\n";
    return s.str();
}

// ---- Scaling ----------------------------------------------------------------------------

bool isTechniquePass(const std::string& pass, const std::string& technique) {
    auto starts = [&](const std::string& prefix) { return pass.compare(0, prefix.size(), prefix) == 0; };
    return starts("gi." + technique + ".") || starts(technique + ".") || starts("gi.voxel.");
}

double fitLogLogSlope(const std::vector<double>& x, const std::vector<double>& y) {
    std::vector<std::pair<double, double>> p; // (log x, log y)
    for (size_t i = 0; i < std::min(x.size(), y.size()); ++i)
        if (x[i] > 0 && y[i] > 0 && std::isfinite(x[i]) && std::isfinite(y[i]))
            p.push_back({std::log(x[i]), std::log(y[i])});
    if (p.empty())
        return NAN;
    double mx = 0, my = 0;
    for (const auto& [lx, ly] : p)
        mx += lx, my += ly;
    mx /= double(p.size()), my /= double(p.size());
    double sxx = 0, sxy = 0;
    for (const auto& [lx, ly] : p)
        sxx += (lx - mx) * (lx - mx), sxy += (lx - mx) * (ly - my);
    return sxx > 0 ? sxy / sxx : NAN;
}

std::string toScalingCsv(const std::vector<ScalingRecord>& records) {
    std::vector<std::string> passes; // union of pass names, first-seen order
    for (const auto& r : records)
        for (const auto& entry : r.passMs)
            if (std::find(passes.begin(), passes.end(), entry.first) == passes.end())
                passes.push_back(entry.first);
    std::ostringstream out;
    out << "axis,value,series,technique,knobs,scene,width,height,triangles,total_ms,technique_ms,wall_ms";
    for (const auto& p : passes)
        out << "," << csvField(p + " ms");
    out << "\n";
    for (const auto& r : records) {
        out << csvField(r.axis) << "," << num(r.value) << "," << csvField(r.series) << "," << csvField(r.technique)
            << "," << csvField(r.knobs) << "," << csvField(r.scene) << "," << r.width << "," << r.height << ","
            << r.triangles << "," << num(r.totalMs) << "," << num(r.techniqueMs) << "," << num(r.wallMs);
        for (const auto& p : passes) {
            auto it = std::find_if(r.passMs.begin(), r.passMs.end(), [&](const auto& e) { return e.first == p; });
            out << "," << (it == r.passMs.end() ? std::string() : num(it->second));
        }
        out << "\n";
    }
    return out.str();
}

std::string toScalingJson(const std::vector<ScalingRecord>& records) {
    nlohmann::json arr = nlohmann::json::array();
    for (const auto& r : records) {
        nlohmann::json passes = nlohmann::json::array();
        for (const auto& entry : r.passMs)
            passes.push_back({{"name", entry.first}, {"ms", entry.second}});
        arr.push_back({{"axis", r.axis},
                       {"value", r.value},
                       {"series", r.series},
                       {"technique", r.technique},
                       {"knobs", r.knobs},
                       {"scene", r.scene},
                       {"width", r.width},
                       {"height", r.height},
                       {"triangles", r.triangles},
                       {"total_ms", r.totalMs},
                       {"technique_ms", r.techniqueMs},
                       {"wall_ms", r.wallMs},
                       {"passes", passes}});
    }
    return arr.dump(2) + "\n";
}

std::string toScalingSvgPlot(const std::vector<ScalingRecord>& records, const std::string& axis) {
    constexpr double W = PlotFrame::W, L = PlotFrame::L, R = PlotFrame::R, T = PlotFrame::T;
    std::vector<std::string> series; // first-seen order
    std::map<std::string, std::vector<std::pair<double, double>>> pts;
    double xMin = INFINITY, xMax = 0, yMin = INFINITY, yMax = 0;
    for (const auto& r : records) {
        if (r.axis != axis || !(r.value > 0) || !(r.totalMs > 0) || !std::isfinite(r.value) || !std::isfinite(r.totalMs))
            continue;
        if (!pts.count(r.series))
            series.push_back(r.series);
        pts[r.series].push_back({r.value, r.totalMs});
        xMin = std::min(xMin, r.value), xMax = std::max(xMax, r.value);
        yMin = std::min(yMin, r.totalMs), yMax = std::max(yMax, r.totalMs);
    }
    std::ostringstream s;
    svgOpen(s, "GPU time against " + axis + " (log-log)");
    if (series.empty())
        return s.str() + "<text x=\"" + num(L) + "\" y=\"80\">no positive measurements</text>\n</svg>\n";
    // The reference line of slope 1 through the first series' first point, over the x range:
    // its y range joins the axis range so the line stays on the canvas.
    auto [x0, y0] = pts[series[0]].front();
    double refLo = y0 * xMin / x0, refHi = y0 * xMax / x0;
    PlotFrame f{logAxis(xMin, xMax), logAxis(std::min(yMin, refLo), std::max(yMax, refHi))};
    svgGrid(s, f, axis, "total GPU ms", false);
    s << "<line x1=\"" << f.X(xMin) << "\" y1=\"" << f.Y(refLo) << "\" x2=\"" << f.X(xMax) << "\" y2=\"" << f.Y(refHi)
      << "\" stroke=\"#888\" stroke-dasharray=\"4 3\"/>\n";
    double ly = T + 10;
    for (size_t k = 0; k < series.size(); ++k) {
        auto& p = pts[series[k]];
        std::sort(p.begin(), p.end());
        const char* colour = kColours[k % 6];
        s << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"1.5\" points=\"";
        for (const auto& [x, y] : p)
            s << f.X(x) << "," << f.Y(y) << " ";
        s << "\"/>\n";
        std::vector<double> xs, ys;
        for (const auto& [x, y] : p) {
            xs.push_back(x), ys.push_back(y);
            s << "<circle cx=\"" << f.X(x) << "\" cy=\"" << f.Y(y) << "\" r=\"3.5\" fill=\"" << colour << "\"><title>"
              << escapeXml(series[k]) << ": " << num(x) << " " << escapeXml(axis) << ", " << num(y)
              << " ms</title></circle>\n";
        }
        double slope = fitLogLogSlope(xs, ys);
        s << "<line x1=\"" << W - R + 12 << "\" y1=\"" << ly << "\" x2=\"" << W - R + 28 << "\" y2=\"" << ly
          << "\" stroke=\"" << colour << "\" stroke-width=\"2\"/><text x=\"" << W - R + 32 << "\" y=\"" << ly + 4
          << "\">" << escapeXml(series[k]) << (std::isfinite(slope) ? " (slope " + num(std::round(slope * 100) / 100) + ")" : "")
          << "</text>\n";
        ly += 20;
    }
    s << "<line x1=\"" << W - R + 12 << "\" y1=\"" << ly << "\" x2=\"" << W - R + 28 << "\" y2=\"" << ly
      << "\" stroke=\"#888\" stroke-dasharray=\"4 3\"/><text x=\"" << W - R + 32 << "\" y=\"" << ly + 4
      << "\">slope 1 (linear)</text>\n</svg>\n";
    return s.str();
}

} // namespace vkgi::gi
