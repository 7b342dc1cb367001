#pragma once
// Bounds-checked reading of glTF accessors (glTF 2.0 §3.6) from a tinygltf::Model. tinygltf parses the JSON
// and buffers but does not guarantee that an accessor's bytes lie inside its buffer view and buffer; every
// read here is checked so that a malformed or truncated file is an InputError, never an out-of-bounds read.
// Errors carry no file name; the loader prefixes it.
#include <cstdint>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace chcrt::detail {

// Reads accessor `index` (`what` names it in errors, e.g. "POSITION") as `components` floats per element.
// Integer component types are converted, and normalised to [0, 1] / [-1, 1] when the accessor is
// `normalized`. Sparse accessors and accessors without a buffer view are rejected (InputError).
std::vector<float> readFloatAccessor(const tinygltf::Model& model, int index, int components, const std::string& what);

// Reads an index accessor: SCALAR of unsigned byte, short or int.
std::vector<uint32_t> readIndexAccessor(const tinygltf::Model& model, int index);

} // namespace chcrt::detail
