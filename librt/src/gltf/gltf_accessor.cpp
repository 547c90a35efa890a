// Accessors to plain arrays. Every byte range is checked against its buffer view (and the
// buffer's real size) before anything is allocated, and the output is charged to the
// Context's allowance, so a huge declared count fails instead of allocating.

#include "gltf/gltf_internal.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

namespace librt::gltf_detail {

namespace {

int component_size(int component_type) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return 4;
        default:
            return 0;  // INT and DOUBLE are not glTF 2.0 accessor types
    }
}

/// A checked view of `count` elements, each `components` values of `component_type`,
/// `stride` bytes apart from `data`.
struct Span {
    const unsigned char* data = nullptr;  // null: zeros (an accessor without buffer view)
    std::size_t count = 0;
    std::size_t stride = 0;
    int components = 0;
    int component_type = 0;
};

/// The bytes [offset, offset + (count - 1) * stride + element) of buffer view `view`,
/// failing (naming `what`) when they do not fit.
const unsigned char* view_range(const tinygltf::Model& model, int view, std::size_t offset,
                                std::size_t count, std::size_t stride, std::size_t element,
                                const std::string& path, const Context& ctx) {
    check_index(ctx, path + ".bufferView", view, model.bufferViews.size(), "buffer view");
    const tinygltf::BufferView& bv = model.bufferViews[static_cast<std::size_t>(view)];
    const unsigned char* bytes = nullptr;
    if (const auto* decoded = ctx.view_bytes(std::size_t(view))) {
        // EXT_meshopt_compression: decoded to at least byteLength bytes.
        bytes = decoded->data();
    } else {
        check_index(ctx, indexed("bufferViews", std::size_t(view)) + ".buffer", bv.buffer,
                    ctx.buffer_count(), "buffer");
        const std::string_view buffer = ctx.buffer(static_cast<std::size_t>(bv.buffer));
        // The view lies in the buffer (checked in the pre-pass against byteLength; checked
        // again here against the bytes really read; a meshopt fallback buffer has none).
        if (bv.byteOffset > buffer.size() || bv.byteLength > buffer.size() - bv.byteOffset)
            ctx.fail(indexed("bufferViews", std::size_t(view)), "lies outside its buffer's data");
        bytes = reinterpret_cast<const unsigned char*>(buffer.data()) + bv.byteOffset;
    }
    // Last byte needed: offset + (count - 1) * stride + element, computed without overflow.
    const std::size_t length = bv.byteLength;
    const bool fits = offset <= length && element <= length - offset &&
                      (count - 1) <= (length - offset - element) / stride;
    if (!fits) {
        ctx.fail(path, std::to_string(count) + " elements of " + std::to_string(element) +
                           " bytes (stride " + std::to_string(stride) + ") from byte " +
                           std::to_string(offset) + " do not fit in bufferViews[" +
                           std::to_string(view) + "] (byteLength " + std::to_string(length) + ")");
    }
    return bytes + offset;
}

/// Value j of element i as float: normalised integers to [0, 1] or [-1, 1] (glTF 2.0
/// spec, "Animations"/"Meshes": c / (2^n - 1) unsigned, max(c / (2^(n-1) - 1), -1) signed).
float component(const Span& s, std::size_t i, int j, bool normalized) {
    if (s.data == nullptr) return 0.0f;
    const unsigned char* p =
        s.data + i * s.stride + std::size_t(j) * std::size_t(component_size(s.component_type));
    switch (s.component_type) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: {
            float f;
            std::memcpy(&f, p, 4);
            return f;
        }
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            const auto c = static_cast<float>(static_cast<signed char>(*p));
            return normalized ? std::max(c / 127.0f, -1.0f) : c;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
            const auto c = static_cast<float>(*p);
            return normalized ? c / 255.0f : c;
        }
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            std::int16_t v;
            std::memcpy(&v, p, 2);
            const auto c = static_cast<float>(v);
            return normalized ? std::max(c / 32767.0f, -1.0f) : c;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            std::uint16_t v;
            std::memcpy(&v, p, 2);
            const auto c = static_cast<float>(v);
            return normalized ? c / 65535.0f : c;
        }
        default: {  // UNSIGNED_INT (indices only)
            std::uint32_t v;
            std::memcpy(&v, p, 4);
            return static_cast<float>(v);
        }
    }
}

std::uint32_t index_at(const Span& s, std::size_t i) {
    if (s.data == nullptr) return 0;
    const unsigned char* p = s.data + i * s.stride;
    switch (s.component_type) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return *p;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            std::uint16_t v;
            std::memcpy(&v, p, 2);
            return v;
        }
        default: {
            std::uint32_t v;
            std::memcpy(&v, p, 4);
            return v;
        }
    }
}

/// The accessor's main data, checked.
Span main_span(const tinygltf::Model& model, const tinygltf::Accessor& a, const std::string& path,
               const Context& ctx) {
    Span s;
    s.components = type_components(a.type);
    s.component_type = a.componentType;
    s.count = a.count;
    const std::size_t element =
        std::size_t(s.components) * std::size_t(component_size(a.componentType));
    if (a.count == 0) ctx.fail(path + ".count", "0: an accessor has at least one element");
    if (a.bufferView < 0) return s;  // zeros, unless sparse
    check_index(ctx, path + ".bufferView", a.bufferView, model.bufferViews.size(), "buffer view");
    const tinygltf::BufferView& bv = model.bufferViews[std::size_t(a.bufferView)];
    s.stride = bv.byteStride != 0 ? bv.byteStride : element;
    if (s.stride < element)
        ctx.fail(path, "byteStride " + std::to_string(s.stride) + " is less than an element of " +
                           std::to_string(element) + " bytes");
    s.data = view_range(model, a.bufferView, a.byteOffset, a.count, s.stride, element, path, ctx);
    return s;
}

const tinygltf::Accessor& checked_accessor(const tinygltf::Model& model, int index,
                                           const std::string& use_path, const Context& ctx,
                                           std::string* path) {
    check_index(ctx, use_path, index, model.accessors.size(), "accessor");
    *path = use_path + ": " + indexed("accessors", std::size_t(index));
    const tinygltf::Accessor& a = model.accessors[std::size_t(index)];
    if (component_size(a.componentType) == 0)
        ctx.fail(*path + ".componentType", std::to_string(a.componentType) + " is not valid");
    if (type_components(a.type) == 0)
        ctx.fail(*path + ".type", "must be SCALAR, VEC2, VEC3 or VEC4 here");
    return a;
}

/// Applies the sparse substitution to `out` (count * components values) through `put`.
template <class Put>
void apply_sparse(const tinygltf::Model& model, const tinygltf::Accessor& a,
                  const std::string& path, Context& ctx, Put put) {
    if (!a.sparse.isSparse) return;
    const std::string sp = path + ".sparse";
    const int n = a.sparse.count;
    if (n < 1 || std::size_t(n) > a.count)
        ctx.fail(sp + ".count", std::to_string(n) + ": must be in [1, accessor count " +
                                    std::to_string(a.count) + "]");
    Span idx;
    idx.component_type = a.sparse.indices.componentType;
    idx.components = 1;
    idx.count = std::size_t(n);
    const int isize = component_size(idx.component_type);
    if (idx.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        idx.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        idx.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        ctx.fail(sp + ".indices.componentType", "must be an unsigned integer type");
    if (a.sparse.indices.byteOffset < 0 || a.sparse.values.byteOffset < 0)
        ctx.fail(sp, "negative byteOffset");
    idx.stride = std::size_t(isize);
    idx.data =
        view_range(model, a.sparse.indices.bufferView, std::size_t(a.sparse.indices.byteOffset),
                   idx.count, idx.stride, idx.stride, sp + ".indices", ctx);
    Span val;
    val.component_type = a.componentType;
    val.components = type_components(a.type);
    val.count = std::size_t(n);
    val.stride = std::size_t(val.components) * std::size_t(component_size(a.componentType));
    val.data =
        view_range(model, a.sparse.values.bufferView, std::size_t(a.sparse.values.byteOffset),
                   val.count, val.stride, val.stride, sp + ".values", ctx);
    std::uint64_t previous = 0;
    for (std::size_t k = 0; k < val.count; ++k) {
        const std::uint32_t target = index_at(idx, k);
        if (target >= a.count || (k > 0 && target <= previous)) {
            ctx.fail(sp + ".indices", "index " + std::to_string(target) + " at position " +
                                          std::to_string(k) +
                                          " is not increasing or not below the accessor count " +
                                          std::to_string(a.count));
        }
        previous = target;
        put(val, k, std::size_t(target));
    }
}

}  // namespace

int type_components(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return 1;
        case TINYGLTF_TYPE_VEC2:
            return 2;
        case TINYGLTF_TYPE_VEC3:
            return 3;
        case TINYGLTF_TYPE_VEC4:
            return 4;
        default:
            return 0;  // matrices are never vertex attributes librt reads
    }
}

std::size_t accessor_count(const tinygltf::Model& model, int index) {
    return model.accessors[std::size_t(index)].count;
}

std::vector<float> read_float_accessor(const tinygltf::Model& model, int index,
                                       const std::vector<int>& types, const std::string& json_path,
                                       Context& ctx, int* components_out) {
    std::string path;
    const tinygltf::Accessor& a = checked_accessor(model, index, json_path, ctx, &path);
    if (std::find(types.begin(), types.end(), a.type) == types.end())
        ctx.fail(path + ".type", "not a type this attribute can have");
    if (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        ctx.fail(path + ".componentType", "UNSIGNED_INT is for indices only");
    const Span s = main_span(model, a, path, ctx);
    const std::size_t total = s.count * std::size_t(s.components);
    ctx.spend(total * sizeof(float), path);
    std::vector<float> out(total);
    if (s.data != nullptr && a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT &&
        s.stride == std::size_t(s.components) * 4) {
        std::memcpy(out.data(), s.data, total * sizeof(float));  // tightly packed floats
    } else if (s.data != nullptr) {
        for (std::size_t i = 0; i < s.count; ++i)
            for (int j = 0; j < s.components; ++j)
                out[i * std::size_t(s.components) + std::size_t(j)] =
                    component(s, i, j, a.normalized);
    }
    apply_sparse(model, a, path, ctx, [&](const Span& val, std::size_t k, std::size_t target) {
        for (int j = 0; j < val.components; ++j)
            out[target * std::size_t(val.components) + std::size_t(j)] =
                component(val, k, j, a.normalized);
    });
    for (std::size_t i = 0; i < total; ++i) {
        if (!std::isfinite(out[i])) {
            ctx.fail(path,
                     "element " + std::to_string(i / std::size_t(s.components)) + " is not finite");
        }
    }
    *components_out = s.components;
    return out;
}

std::vector<std::uint32_t> read_index_accessor(const tinygltf::Model& model, int index,
                                               const std::string& json_path, Context& ctx) {
    std::string path;
    const tinygltf::Accessor& a = checked_accessor(model, index, json_path, ctx, &path);
    if (a.type != TINYGLTF_TYPE_SCALAR) ctx.fail(path + ".type", "indices must be SCALAR");
    if (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        ctx.fail(path + ".componentType", "indices must be UNSIGNED_BYTE, _SHORT or _INT");
    const Span s = main_span(model, a, path, ctx);
    ctx.spend(s.count * sizeof(std::uint32_t), path);
    std::vector<std::uint32_t> out(s.count);
    for (std::size_t i = 0; i < s.count; ++i) out[i] = index_at(s, i);
    apply_sparse(model, a, path, ctx, [&](const Span& val, std::size_t k, std::size_t target) {
        out[target] = index_at(val, k);
    });
    return out;
}

}  // namespace librt::gltf_detail
