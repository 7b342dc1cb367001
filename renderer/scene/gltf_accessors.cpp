#include "renderer/scene/gltf_accessors.h"

#include "renderer/core/error.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <bit>
#include <cstring>

namespace chcrt::detail {

// glTF buffers are little-endian; the component reads below memcpy them as native values.
static_assert(std::endian::native == std::endian::little, "glTF accessor reads assume a little-endian host");

namespace {

// One accessor's bytes after all range checks: element i starts at data + i * stride.
struct AccessorView {
    const uint8_t* data = nullptr; // null: no buffer view, all elements are zero
    size_t count = 0;
    size_t stride = 0;
    int componentType = 0;
    int components = 0;
    bool normalized = false;
};

std::string accessorName(int index, const std::string& what) {
    return "accessor " + std::to_string(index) + " (" + what + ")";
}

AccessorView viewAccessor(const tinygltf::Model& model, int index, const std::string& what) {
    if (index < 0 || static_cast<size_t>(index) >= model.accessors.size())
        throw InputError(what + " refers to missing accessor " + std::to_string(index));
    const tinygltf::Accessor& accessor = model.accessors[index];
    const std::string name = accessorName(index, what);
    if (accessor.sparse.isSparse) throw InputError(name + " is sparse; sparse accessors are not supported");
    AccessorView view;
    view.count = accessor.count;
    view.componentType = accessor.componentType;
    view.normalized = accessor.normalized;
    view.components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(accessor.type));
    const int componentSize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(accessor.componentType));
    if (view.components <= 0 || componentSize <= 0) throw InputError(name + " has an invalid type or component type");
    const size_t elementSize = size_t(view.components) * size_t(componentSize);
    // Without a buffer view an accessor is all zeros (useful only with sparse data, rejected above); zero
    // positions or indices cannot form triangles, so this is malformed input here.
    if (accessor.bufferView < 0) throw InputError(name + " has no bufferView");

    if (static_cast<size_t>(accessor.bufferView) >= model.bufferViews.size())
        throw InputError(name + " refers to missing buffer view " + std::to_string(accessor.bufferView));
    const tinygltf::BufferView& bufferView = model.bufferViews[accessor.bufferView];
    if (bufferView.buffer < 0 || static_cast<size_t>(bufferView.buffer) >= model.buffers.size())
        throw InputError(name + ": buffer view refers to missing buffer " + std::to_string(bufferView.buffer));
    const std::vector<unsigned char>& buffer = model.buffers[bufferView.buffer].data;
    if (bufferView.byteLength > buffer.size() || bufferView.byteOffset > buffer.size() - bufferView.byteLength)
        throw InputError(name + ": buffer view " + std::to_string(accessor.bufferView) + " exceeds its buffer (" +
                         std::to_string(buffer.size()) + " bytes; truncated file?)");
    view.stride = bufferView.byteStride != 0 ? bufferView.byteStride : elementSize;
    if (view.stride < elementSize) throw InputError(name + " has a byteStride smaller than its element size");
    if (view.count == 0) return view;
    // Last byte read: byteOffset + stride * (count - 1) + elementSize, checked without overflow.
    const size_t length = bufferView.byteLength;
    if (accessor.byteOffset > length || elementSize > length - accessor.byteOffset ||
        (view.count - 1) > (length - accessor.byteOffset - elementSize) / view.stride)
        throw InputError(name + " with " + std::to_string(view.count) + " elements exceeds its buffer view (" +
                         std::to_string(length) + " bytes)");
    view.data = buffer.data() + bufferView.byteOffset + accessor.byteOffset;
    return view;
}

template <typename T> T load(const uint8_t* p) {
    T value;
    std::memcpy(&value, p, sizeof(T));
    return value;
}

// One component as float; normalised integers follow glTF 2.0 §3.11 (signed: max(c / MAX, -1)).
float readComponent(const uint8_t* p, int componentType, bool normalized) {
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return load<float>(p);
    case TINYGLTF_COMPONENT_TYPE_DOUBLE: return static_cast<float>(load<double>(p));
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? load<uint8_t>(p) / 255.0f : load<uint8_t>(p);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return normalized ? load<uint16_t>(p) / 65535.0f : load<uint16_t>(p);
    case TINYGLTF_COMPONENT_TYPE_BYTE: return normalized ? std::max(load<int8_t>(p) / 127.0f, -1.0f) : load<int8_t>(p);
    case TINYGLTF_COMPONENT_TYPE_SHORT:
        return normalized ? std::max(load<int16_t>(p) / 32767.0f, -1.0f) : load<int16_t>(p);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return static_cast<float>(load<uint32_t>(p));
    case TINYGLTF_COMPONENT_TYPE_INT: return static_cast<float>(load<int32_t>(p));
    default: return 0.0f;
    }
}

} // namespace

std::vector<float> readFloatAccessor(const tinygltf::Model& model, int index, int components, const std::string& what) {
    const AccessorView view = viewAccessor(model, index, what);
    if (view.components != components)
        throw InputError(accessorName(index, what) + " has " + std::to_string(view.components) +
                         " components per element, expected " + std::to_string(components));
    std::vector<float> values(view.count * size_t(components), 0.0f);
    if (!view.data) return values;
    const int componentSize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(view.componentType));
    for (size_t i = 0; i < view.count; ++i) {
        const uint8_t* element = view.data + i * view.stride;
        for (int c = 0; c < components; ++c)
            values[i * components + c] = readComponent(element + c * componentSize, view.componentType, view.normalized);
    }
    return values;
}

std::vector<uint32_t> readIndexAccessor(const tinygltf::Model& model, int index) {
    const AccessorView view = viewAccessor(model, index, "indices");
    if (view.components != 1) throw InputError(accessorName(index, "indices") + " is not SCALAR");
    std::vector<uint32_t> indices(view.count, 0u);
    if (!view.data) return indices;
    for (size_t i = 0; i < view.count; ++i) {
        const uint8_t* p = view.data + i * view.stride;
        switch (view.componentType) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: indices[i] = load<uint8_t>(p); break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: indices[i] = load<uint16_t>(p); break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: indices[i] = load<uint32_t>(p); break;
        default:
            throw InputError(accessorName(index, "indices") +
                             " must be unsigned byte, short or int, not component type " +
                             std::to_string(view.componentType));
        }
    }
    return indices;
}

} // namespace chcrt::detail
