// Minimal SPIR-V reflection: descriptor bindings (set, binding, type, count, readonly /
// writeonly), push-constant
// block size and compute local size. Enough for vkgi's shaders; unknown constructs are errors.
#include <algorithm>
#include <map>
#include <string>
#include <unordered_map>

#include "vkgi/pipeline.hpp"

namespace vkgi {

namespace {

enum Op : uint32_t {
    OpName = 5, OpEntryPoint = 15, OpExecutionMode = 16, OpTypeInt = 21, OpTypeFloat = 22, OpTypeVector = 23,
    OpTypeMatrix = 24, OpTypeImage = 25, OpTypeSampler = 26, OpTypeSampledImage = 27, OpTypeArray = 28,
    OpTypeRuntimeArray = 29, OpTypeStruct = 30, OpTypePointer = 32, OpConstant = 43, OpVariable = 59,
    OpDecorate = 71, OpMemberDecorate = 72, OpExecutionModeId = 331, OpTypeAccelerationStructure = 5341
};
enum Decoration : uint32_t {
    DecBlock = 2, DecBufferBlock = 3, DecArrayStride = 6, DecMatrixStride = 7, DecNonWritable = 24,
    DecNonReadable = 25, DecBinding = 33, DecSet = 34, DecOffset = 35
};
enum StorageClass : uint32_t { ScUniformConstant = 0, ScUniform = 2, ScPushConstant = 9, ScStorageBuffer = 12 };

struct TypeInfo {
    uint32_t op = 0;
    std::vector<uint32_t> w; // operands after the result id
};

struct Parser {
    std::unordered_map<uint32_t, TypeInfo> types;
    std::unordered_map<uint32_t, uint32_t> constants;
    std::unordered_map<uint32_t, std::string> names;
    std::unordered_map<uint32_t, std::map<uint32_t, uint32_t>> decorations;           // id -> dec -> value
    std::unordered_map<uint32_t, std::map<uint32_t, uint32_t>> memberOffsets;         // struct -> member -> offset
    std::unordered_map<uint32_t, std::map<uint32_t, uint32_t>> memberMatrixStrides;   // struct -> member -> stride
    std::unordered_map<uint32_t, std::map<uint32_t, uint32_t>> memberAccess; // struct -> member -> NonWritable/NonReadable bits
    struct Var {
        uint32_t type, id, storage;
    };
    std::vector<Var> vars;

    uint32_t sizeOf(uint32_t typeId, uint32_t matrixStride = 16) const {
        auto it = types.find(typeId);
        if (it == types.end())
            return 0;
        const TypeInfo& t = it->second;
        switch (t.op) {
        case OpTypeInt:
        case OpTypeFloat:
            return t.w[0] / 8;
        case OpTypeVector:
            return sizeOf(t.w[0]) * t.w[1];
        case OpTypeMatrix:
            return matrixStride * t.w[1];
        case OpTypeArray: {
            uint32_t stride = decorationOf(typeId, DecArrayStride, sizeOf(t.w[0]));
            auto c = constants.find(t.w[1]);
            return stride * (c == constants.end() ? 1 : c->second);
        }
        case OpTypeStruct: {
            uint32_t size = 0;
            auto offs = memberOffsets.find(typeId);
            for (uint32_t m = 0; m < t.w.size(); ++m) {
                uint32_t off = 0;
                if (offs != memberOffsets.end() && offs->second.count(m))
                    off = offs->second.at(m);
                uint32_t ms = 16;
                if (auto s = memberMatrixStrides.find(typeId); s != memberMatrixStrides.end() && s->second.count(m))
                    ms = s->second.at(m);
                size = std::max(size, off + sizeOf(t.w[m], ms));
            }
            return size;
        }
        default:
            return 0;
        }
    }

    uint32_t decorationOf(uint32_t id, uint32_t dec, uint32_t fallback) const {
        auto it = decorations.find(id);
        if (it == decorations.end() || !it->second.count(dec))
            return fallback;
        return it->second.at(dec);
    }
    bool hasDecoration(uint32_t id, uint32_t dec) const {
        auto it = decorations.find(id);
        return it != decorations.end() && it->second.count(dec);
    }
};

std::string literalString(const uint32_t* w, size_t maxWords) {
    std::string s;
    const char* c = reinterpret_cast<const char*>(w);
    for (size_t i = 0; i < maxWords * 4 && c[i]; ++i)
        s += c[i];
    return s;
}

Result<VkDescriptorType> descriptorType(const Parser& p, uint32_t typeId, uint32_t storage, uint32_t& count) {
    count = 1;
    auto t = p.types.find(typeId);
    while (t != p.types.end() && (t->second.op == OpTypeArray || t->second.op == OpTypeRuntimeArray)) {
        if (t->second.op == OpTypeArray) {
            auto c = p.constants.find(t->second.w[1]);
            count *= c == p.constants.end() ? 1 : c->second;
        } else {
            count = 0; // runtime array: bindless, unsupported on lavapipe
        }
        typeId = t->second.w[0];
        t = p.types.find(typeId);
    }
    if (t == p.types.end())
        return makeError("unknown descriptor type id " + std::to_string(typeId));
    const TypeInfo& ti = t->second;
    switch (ti.op) {
    case OpTypeSampler:
        return VK_DESCRIPTOR_TYPE_SAMPLER;
    case OpTypeSampledImage:
        return VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    case OpTypeImage: {
        uint32_t dim = ti.w[1], sampled = ti.w[5];
        if (dim == 5) // Buffer
            return sampled == 2 ? VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER : VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
        return sampled == 2 ? VK_DESCRIPTOR_TYPE_STORAGE_IMAGE : VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
    }
    case OpTypeStruct:
        if (storage == ScStorageBuffer || p.hasDecoration(typeId, DecBufferBlock))
            return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        return VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    default:
        return makeError("unsupported descriptor type (op " + std::to_string(ti.op) + ")");
    }
}

// The element type of a (possibly arrayed) descriptor.
uint32_t elementType(const Parser& p, uint32_t typeId) {
    auto t = p.types.find(typeId);
    while (t != p.types.end() && (t->second.op == OpTypeArray || t->second.op == OpTypeRuntimeArray)) {
        typeId = t->second.w[0];
        t = p.types.find(typeId);
    }
    return typeId;
}

// GLSL's readonly / writeonly: NonWritable / NonReadable on the variable, or on every member
// of a buffer block. Sampled images, samplers and uniform buffers are never written.
void accessQualifiers(const Parser& p, uint32_t varId, uint32_t pointee, ReflectedBinding& b) {
    switch (b.type) {
    case VK_DESCRIPTOR_TYPE_STORAGE_IMAGE:
    case VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER:
    case VK_DESCRIPTOR_TYPE_STORAGE_BUFFER:
        break;
    default:
        b.readable = true;
        b.writable = false;
        return;
    }
    bool nonWritable = p.hasDecoration(varId, DecNonWritable);
    bool nonReadable = p.hasDecoration(varId, DecNonReadable);
    const uint32_t block = elementType(p, pointee);
    auto t = p.types.find(block);
    if (t != p.types.end() && t->second.op == OpTypeStruct && !t->second.w.empty()) {
        auto m = p.memberAccess.find(block);
        bool allNonWritable = true, allNonReadable = true;
        for (uint32_t i = 0; i < t->second.w.size(); ++i) {
            uint32_t bits = 0;
            if (m != p.memberAccess.end())
                if (auto it = m->second.find(i); it != m->second.end())
                    bits = it->second;
            allNonWritable = allNonWritable && (bits & 1u);
            allNonReadable = allNonReadable && (bits & 2u);
        }
        nonWritable = nonWritable || allNonWritable;
        nonReadable = nonReadable || allNonReadable;
    }
    b.readable = !nonReadable;
    b.writable = !nonWritable;
}

VkShaderStageFlagBits stageOf(uint32_t model) {
    switch (model) {
    case 0: return VK_SHADER_STAGE_VERTEX_BIT;
    case 3: return VK_SHADER_STAGE_GEOMETRY_BIT;
    case 4: return VK_SHADER_STAGE_FRAGMENT_BIT;
    case 5: return VK_SHADER_STAGE_COMPUTE_BIT;
    default: return VK_SHADER_STAGE_ALL;
    }
}

} // namespace

Result<ShaderReflection> reflectSpirv(std::span<const uint32_t> code) {
    if (code.size() < 5 || code[0] != 0x07230203u)
        return makeError("not a SPIR-V module (bad magic)");
    Parser p;
    ShaderReflection out;
    uint32_t localSizeIds[3] = {0, 0, 0}; // LocalSizeId operands are constants defined later
    for (size_t i = 5; i < code.size();) {
        uint32_t words = code[i] >> 16, op = code[i] & 0xffffu;
        if (words == 0 || i + words > code.size())
            return makeError("truncated SPIR-V instruction at word " + std::to_string(i));
        const uint32_t* w = &code[i + 1];
        uint32_t n = words - 1;
        switch (op) {
        case OpName:
            p.names[w[0]] = literalString(w + 1, n - 1);
            break;
        case OpEntryPoint:
            out.stage = stageOf(w[0]);
            break;
        case OpExecutionMode:
            if (w[1] == 17 && n >= 5) // LocalSize
                out.localSize[0] = w[2], out.localSize[1] = w[3], out.localSize[2] = w[4];
            break;
        case OpExecutionModeId:
            if (w[1] == 38 && n >= 5) // LocalSizeId
                localSizeIds[0] = w[2], localSizeIds[1] = w[3], localSizeIds[2] = w[4];
            break;
        case OpTypeInt: case OpTypeFloat: case OpTypeVector: case OpTypeMatrix: case OpTypeImage:
        case OpTypeSampler: case OpTypeSampledImage: case OpTypeArray: case OpTypeRuntimeArray:
        case OpTypeStruct: case OpTypePointer: case OpTypeAccelerationStructure:
            p.types[w[0]] = TypeInfo{op, std::vector<uint32_t>(w + 1, w + n)};
            break;
        case OpConstant:
            if (n >= 3)
                p.constants[w[1]] = w[2];
            break;
        case OpVariable:
            p.vars.push_back({w[0], w[1], w[2]});
            break;
        case OpDecorate:
            p.decorations[w[0]][w[1]] = n >= 3 ? w[2] : 1;
            break;
        case OpMemberDecorate:
            if (w[2] == DecOffset && n >= 4)
                p.memberOffsets[w[0]][w[1]] = w[3];
            if (w[2] == DecMatrixStride && n >= 4)
                p.memberMatrixStrides[w[0]][w[1]] = w[3];
            if (w[2] == DecNonWritable)
                p.memberAccess[w[0]][w[1]] |= 1u;
            if (w[2] == DecNonReadable)
                p.memberAccess[w[0]][w[1]] |= 2u;
            break;
        default:
            break;
        }
        i += words;
    }
    for (int i = 0; i < 3; ++i)
        if (localSizeIds[i] && p.constants.count(localSizeIds[i]))
            out.localSize[i] = p.constants.at(localSizeIds[i]);
    for (const auto& v : p.vars) {
        auto ptr = p.types.find(v.type);
        if (ptr == p.types.end() || ptr->second.op != OpTypePointer)
            continue;
        uint32_t pointee = ptr->second.w[1];
        if (v.storage == ScPushConstant) {
            out.pushConstantSize = p.sizeOf(pointee);
            continue;
        }
        if (v.storage != ScUniformConstant && v.storage != ScUniform && v.storage != ScStorageBuffer)
            continue;
        if (!p.hasDecoration(v.id, DecBinding))
            continue;
        ReflectedBinding b;
        b.set = p.decorationOf(v.id, DecSet, 0);
        b.binding = p.decorationOf(v.id, DecBinding, 0);
        auto type = descriptorType(p, pointee, v.storage, b.count);
        if (!type)
            return makeError("binding " + std::to_string(b.binding) + ": " + type.error().message);
        if (b.count == 0)
            return makeError("binding " + std::to_string(b.binding) + ": runtime descriptor arrays are not supported");
        b.type = *type;
        accessQualifiers(p, v.id, pointee, b);
        auto nm = p.names.find(v.id);
        if (nm == p.names.end() || nm->second.empty())
            nm = p.names.find(pointee);
        b.name = nm != p.names.end() ? nm->second : std::string();
        out.bindings.push_back(b);
    }
    std::sort(out.bindings.begin(), out.bindings.end(), [](const ReflectedBinding& a, const ReflectedBinding& b) {
        return a.set != b.set ? a.set < b.set : a.binding < b.binding;
    });
    return out;
}

} // namespace vkgi
