// writeDot(): the compiled graph as Graphviz, for debugging and the docs.
#include <ostream>

#include "vkgi/rg/render_graph.hpp"

namespace vkgi::rg {

namespace {

// DOT string literal: names come from user code, so quotes and backslashes are escaped.
std::string escaped(const std::string& text) {
    std::string out;
    for (char c : text) {
        if (c == '"' || c == '\\')
            out += '\\';
        out += c;
    }
    return out;
}

std::string versionId(uint32_t resource, uint32_t version) {
    return "r" + std::to_string(resource) + "_" + std::to_string(version);
}

} // namespace

void RenderGraph::writeDot(std::ostream& out) const {
    out << "digraph rendergraph {\n  rankdir=LR;\n  node [fontname=\"Helvetica\"];\n";
    for (uint32_t p = 0; p < m_passes.size(); ++p) {
        const detail::PassNode& pass = m_passes[p];
        out << "  p" << p << " [shape=box, label=\"" << escaped(pass.name) << "\"";
        if (pass.culled)
            out << ", style=\"filled,dashed\", fillcolor=lightgrey, fontcolor=grey40, color=grey60";
        else
            out << ", style=filled, fillcolor=" << (pass.sideEffect ? "orange" : "lightskyblue");
        out << "];\n";
    }
    for (uint32_t r = 0; r < m_resources.size(); ++r) {
        const detail::ResourceNode& res = m_resources[r];
        const char* colour = res.origin == detail::Origin::Transient ? "palegreen" : "khaki";
        // Version 0 of a transient has no contents and no edges (reading it is an error).
        uint32_t first = res.origin == detail::Origin::Transient ? 1 : 0;
        for (uint32_t v = first; v < res.producers.size(); ++v)
            out << "  " << versionId(r, v) << " [shape=ellipse, style=filled, fillcolor=" << colour << ", label=\""
                << escaped(res.name) << "\\nv" << v << "\"];\n";
    }
    for (uint32_t p = 0; p < m_passes.size(); ++p) {
        for (auto [r, v] : m_passes[p].reads)
            out << "  " << versionId(r, v) << " -> p" << p << ";\n";
        for (auto [r, v] : m_passes[p].writes)
            out << "  p" << p << " -> " << versionId(r, v) << " [color=firebrick];\n";
    }
    out << "}\n";
}

} // namespace vkgi::rg
