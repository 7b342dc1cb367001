// PLY (Stanford polygon format, as documented by Greg Turk, 1994): ASCII and binary little/big endian.
// The header declares elements with typed properties; `vertex` (x, y, z, optional nx/ny/nz and u/v or s/t)
// and `face` (a list property `vertex_indices` or `vertex_index`) are used, everything else is read and
// skipped. Polygons are fan-triangulated. Strict: any header or data problem is an InputError that names the
// file and what is wrong.
#include "renderer/core/error.h"
#include "renderer/scene/mesh_utils.h"
#include "renderer/scene/scene_loader.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>

namespace chcrt {

namespace {

using detail::throwFileError;

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64, Invalid };
enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::Invalid; // the item type for lists
    bool isList = false;
    PlyType countType = PlyType::Invalid;
};

struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<PlyProperty> properties;
};

struct PlyHeader {
    PlyFormat format = PlyFormat::Ascii;
    std::vector<PlyElement> elements;
    size_t dataOffset = 0; // first byte after "end_header\n"
};

PlyType parseType(const std::string& name) {
    if (name == "char" || name == "int8") return PlyType::Int8;
    if (name == "uchar" || name == "uint8") return PlyType::UInt8;
    if (name == "short" || name == "int16") return PlyType::Int16;
    if (name == "ushort" || name == "uint16") return PlyType::UInt16;
    if (name == "int" || name == "int32") return PlyType::Int32;
    if (name == "uint" || name == "uint32") return PlyType::UInt32;
    if (name == "float" || name == "float32") return PlyType::Float32;
    if (name == "double" || name == "float64") return PlyType::Float64;
    return PlyType::Invalid;
}

bool isIntegerType(PlyType type) { return type != PlyType::Float32 && type != PlyType::Float64 && type != PlyType::Invalid; }

size_t typeBytes(PlyType type) {
    switch (type) {
    case PlyType::Int8: case PlyType::UInt8: return 1;
    case PlyType::Int16: case PlyType::UInt16: return 2;
    case PlyType::Float64: return 8;
    default: return 4;
    }
}

// The counts are untrusted: an element whose items could not fit in the data that follows the header (each
// binary property takes its type's size, or its count's for a list; each ASCII value at least one character)
// is rejected before any item is read, and so is an element with items but no properties, whose items take no
// bytes and whose count alone would decide how long the loop runs.
void checkElementCounts(const PlyHeader& header, uint64_t dataBytes, const std::filesystem::path& file) {
    uint64_t needed = 0;
    for (const PlyElement& element : header.elements) {
        if (element.count == 0) continue;
        if (element.properties.empty())
            throwFileError(file, "PLY element '" + element.name + "' has " + std::to_string(element.count) +
                                     " items but no properties");
        uint64_t itemBytes = 0;
        for (const PlyProperty& property : element.properties)
            itemBytes += header.format == PlyFormat::Ascii ? 1 : typeBytes(property.isList ? property.countType : property.type);
        if (element.count > (dataBytes - std::min(needed, dataBytes)) / itemBytes)
            throwFileError(file, "truncated data in element '" + element.name + "' (it declares " +
                                     std::to_string(element.count) + " items, more than the " +
                                     std::to_string(dataBytes) + " bytes after the header can hold)");
        needed += element.count * itemBytes;
    }
}

// Parses the header line by line; `bytes` is the whole file.
PlyHeader parseHeader(const std::string& bytes, const std::filesystem::path& file) {
    PlyHeader header;
    size_t pos = 0;
    size_t lineNumber = 0;
    bool sawFormat = false;
    const auto nextLine = [&](std::string& line) {
        if (pos >= bytes.size()) return false;
        size_t end = bytes.find('\n', pos);
        if (end == std::string::npos) end = bytes.size();
        line.assign(bytes, pos, end - pos);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        pos = std::min(end + 1, bytes.size());
        ++lineNumber;
        return true;
    };
    std::string line;
    if (!nextLine(line) || line != "ply") throwFileError(file, "not a PLY file (first line is not 'ply')");
    while (true) {
        if (!nextLine(line)) throwFileError(file, "PLY header has no end_header");
        const auto fail = [&](const std::string& what) {
            throwFileError(file, "PLY header line " + std::to_string(lineNumber) + ": " + what + " ('" + line + "')");
        };
        std::istringstream words(line);
        std::string keyword;
        words >> keyword;
        if (keyword.empty() || keyword == "comment" || keyword == "obj_info") continue;
        if (keyword == "end_header") break;
        if (keyword == "format") {
            std::string format, version;
            words >> format >> version;
            if (format == "ascii") header.format = PlyFormat::Ascii;
            else if (format == "binary_little_endian") header.format = PlyFormat::BinaryLittleEndian;
            else if (format == "binary_big_endian") header.format = PlyFormat::BinaryBigEndian;
            else fail("unknown format '" + format + "'");
            if (version != "1.0") fail("unsupported version '" + version + "'");
            sawFormat = true;
        } else if (keyword == "element") {
            PlyElement element;
            std::string count;
            words >> element.name >> count;
            const auto [end, ec] = std::from_chars(count.data(), count.data() + count.size(), element.count);
            if (element.name.empty() || ec != std::errc() || end != count.data() + count.size())
                fail("bad element declaration");
            header.elements.push_back(std::move(element));
        } else if (keyword == "property") {
            if (header.elements.empty()) fail("property before any element");
            PlyProperty property;
            std::string type;
            words >> type;
            if (type == "list") {
                std::string countType, itemType;
                words >> countType >> itemType >> property.name;
                property.isList = true;
                property.countType = parseType(countType);
                property.type = parseType(itemType);
                if (!isIntegerType(property.countType)) fail("list count type must be an integer type");
            } else {
                words >> property.name;
                property.type = parseType(type);
            }
            if (property.type == PlyType::Invalid || property.name.empty()) fail("bad property declaration");
            header.elements.back().properties.push_back(std::move(property));
        } else {
            fail("unknown header keyword '" + keyword + "'");
        }
    }
    if (!sawFormat) throwFileError(file, "PLY header has no format line");
    header.dataOffset = pos;
    checkElementCounts(header, bytes.size() - pos, file);
    return header;
}

struct TruncatedData {};
struct BadValue {
    std::string what;
};

// Binary values with bounds checks; big-endian values are byte-swapped.
class BinaryReader {
public:
    BinaryReader(const char* begin, const char* end, bool bigEndian) : cur_(begin), end_(end), swap_(bigEndian) {}

    double readNumber(PlyType type) {
        switch (type) {
        case PlyType::Int8: return load<int8_t>();
        case PlyType::UInt8: return load<uint8_t>();
        case PlyType::Int16: return load<int16_t>();
        case PlyType::UInt16: return load<uint16_t>();
        case PlyType::Int32: return load<int32_t>();
        case PlyType::UInt32: return load<uint32_t>();
        case PlyType::Float32: return load<float>();
        case PlyType::Float64: return load<double>();
        default: return 0.0;
        }
    }
    int64_t readInteger(PlyType type) {
        switch (type) {
        case PlyType::Int8: return load<int8_t>();
        case PlyType::UInt8: return load<uint8_t>();
        case PlyType::Int16: return load<int16_t>();
        case PlyType::UInt16: return load<uint16_t>();
        case PlyType::Int32: return load<int32_t>();
        case PlyType::UInt32: return load<uint32_t>();
        default: return 0;
        }
    }
    size_t remaining() const { return static_cast<size_t>(end_ - cur_); }
    std::string location() const { return ""; }

private:
    template <typename T> T load() {
        if (static_cast<size_t>(end_ - cur_) < sizeof(T)) throw TruncatedData{};
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, cur_, sizeof(T));
        cur_ += sizeof(T);
        if (swap_ != (std::endian::native == std::endian::big)) std::reverse(raw, raw + sizeof(T));
        T value;
        std::memcpy(&value, raw, sizeof(T));
        return value;
    }
    const char* cur_;
    const char* end_;
    bool swap_; // true when the file is big-endian
};

// Whitespace-separated ASCII numbers; tracks the line for error messages.
class AsciiReader {
public:
    AsciiReader(const char* begin, const char* end, size_t firstLine) : cur_(begin), end_(end), line_(firstLine) {}

    double readNumber(PlyType type) {
        if (isIntegerType(type)) return static_cast<double>(readInteger(type));
        const std::string_view token = nextToken();
        double value = 0.0;
        const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
        // from_chars rejects out-of-range values; strtod turns overflow (1e999) into +-inf, which validation
        // reports, and underflow (1e-999) into zero.
        if (ec == std::errc::result_out_of_range) return std::strtod(std::string(token).c_str(), nullptr);
        if (ec != std::errc() || end != token.data() + token.size()) throw BadValue{"bad number '" + std::string(token) + "'"};
        return value;
    }
    int64_t readInteger(PlyType) {
        const std::string_view token = nextToken();
        int64_t value = 0;
        const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
        if (ec != std::errc() || end != token.data() + token.size())
            throw BadValue{"bad integer '" + std::string(token) + "'"};
        return value;
    }
    size_t remaining() const { return static_cast<size_t>(end_ - cur_); }
    std::string location() const { return " on line " + std::to_string(line_); }

private:
    std::string_view nextToken() {
        while (cur_ < end_ && (*cur_ == ' ' || *cur_ == '\t' || *cur_ == '\n' || *cur_ == '\r')) {
            if (*cur_ == '\n') ++line_;
            ++cur_;
        }
        const char* start = cur_;
        while (cur_ < end_ && !(*cur_ == ' ' || *cur_ == '\t' || *cur_ == '\n' || *cur_ == '\r')) ++cur_;
        if (start == cur_) throw TruncatedData{};
        return {start, static_cast<size_t>(cur_ - start)};
    }
    const char* cur_;
    const char* end_;
    size_t line_;
};

// Where each vertex property goes: slot 0-2 position, 3-5 normal, 6-7 texture coordinate, -1 ignored.
int vertexSlot(const std::string& name) {
    static const char* const kNames[][3] = {{"x", nullptr, nullptr},       {"y", nullptr, nullptr},
                                            {"z", nullptr, nullptr},       {"nx", nullptr, nullptr},
                                            {"ny", nullptr, nullptr},      {"nz", nullptr, nullptr},
                                            {"u", "s", "texture_u"},       {"v", "t", "texture_v"}};
    for (int slot = 0; slot < 8; ++slot)
        for (const char* alias : kNames[slot])
            if (alias && name == alias) return slot;
    return -1;
}

class PlyDecoder {
public:
    PlyDecoder(const PlyHeader& header, const std::filesystem::path& file, Progress& progress)
        : header_(header), file_(file), progress_(progress) {
        for (const PlyElement& element : header.elements)
            if (element.name == "vertex") vertexCount_ = element.count;
    }

    template <typename Reader> void decode(Reader& reader, Scene& scene) {
        uint64_t totalItems = 0;
        for (const PlyElement& element : header_.elements) totalItems += element.count;
        progress_.begin("Loading " + file_.filename().string(), totalItems);
        try {
            decodeElements(reader, scene);
        } catch (...) {
            progress_.end(); // every begin() gets its end(), also on errors
            throw;
        }
        progress_.end();
    }

    uint64_t degenerateFaces() const { return degenerateFaces_; }

private:
    template <typename Reader> void decodeElements(Reader& reader, Scene& scene) {
        uint64_t doneItems = 0;
        for (const PlyElement& element : header_.elements) {
            uint64_t item = 0;
            try {
                if (element.name == "vertex") readVertices(reader, element, scene, item, doneItems);
                else if (element.name == "face") readFaces(reader, element, scene, item, doneItems);
                else for (; item < element.count; ++item) skipItem(reader, element);
            } catch (const TruncatedData&) {
                throwFileError(file_, "truncated data in element '" + element.name + "' (item " + std::to_string(item) +
                                          " of " + std::to_string(element.count) + ")");
            } catch (const BadValue& bad) {
                throwFileError(file_, bad.what + reader.location() + " in element '" + element.name + "' (item " +
                                          std::to_string(item) + ")");
            }
            doneItems += element.count;
        }
    }

    template <typename Reader> void skipItem(Reader& reader, const PlyElement& element) {
        for (const PlyProperty& property : element.properties) {
            if (!property.isList) {
                reader.readNumber(property.type);
                continue;
            }
            const int64_t count = readListCount(reader, property);
            for (int64_t i = 0; i < count; ++i) reader.readNumber(property.type);
        }
    }

    template <typename Reader> int64_t readListCount(Reader& reader, const PlyProperty& property) {
        const int64_t count = reader.readInteger(property.countType);
        if (count < 0) throw BadValue{"negative list length " + std::to_string(count)};
        return count;
    }

    // Never reserve more items than the remaining bytes could hold (every property takes at least one byte),
    // so a corrupt count cannot allocate gigabytes before the truncation is noticed.
    template <typename Reader> size_t safeReserve(const Reader& reader, const PlyElement& element) const {
        const uint64_t minimumItemBytes = std::max<uint64_t>(1, element.properties.size());
        return static_cast<size_t>(std::min<uint64_t>(element.count, reader.remaining() / minimumItemBytes));
    }

    template <typename Reader>
    void readVertices(Reader& reader, const PlyElement& element, Scene& scene, uint64_t& item, uint64_t doneBefore) {
        std::vector<int> slots;
        bool present[8] = {};
        for (const PlyProperty& property : element.properties) {
            const int slot = property.isList ? -1 : vertexSlot(property.name);
            slots.push_back(slot);
            if (slot >= 0) present[slot] = true;
        }
        if (!present[0] || !present[1] || !present[2]) throwFileError(file_, "element 'vertex' lacks x, y or z");
        const bool hasNormals = present[3] && present[4] && present[5];
        const bool hasTexcoords = present[6] && present[7];
        scene.positions.reserve(safeReserve(reader, element));
        for (; item < element.count; ++item) {
            double values[8] = {};
            for (size_t p = 0; p < element.properties.size(); ++p) {
                const PlyProperty& property = element.properties[p];
                if (property.isList) {
                    const int64_t count = readListCount(reader, property);
                    for (int64_t i = 0; i < count; ++i) reader.readNumber(property.type);
                } else {
                    const double value = reader.readNumber(property.type);
                    if (slots[p] >= 0) values[slots[p]] = value;
                }
            }
            scene.positions.emplace_back(values[0], values[1], values[2]);
            if (hasNormals) scene.normals.emplace_back(values[3], values[4], values[5]);
            if (hasTexcoords) scene.texcoords.emplace_back(values[6], values[7]);
            if ((item & 0xFFFF) == 0) progress_.update(doneBefore + item);
        }
    }

    template <typename Reader>
    void readFaces(Reader& reader, const PlyElement& element, Scene& scene, uint64_t& item, uint64_t doneBefore) {
        int indexProperty = -1;
        for (size_t p = 0; p < element.properties.size(); ++p) {
            const PlyProperty& property = element.properties[p];
            if (property.isList && (property.name == "vertex_indices" || property.name == "vertex_index"))
                indexProperty = static_cast<int>(p);
        }
        if (indexProperty < 0) throwFileError(file_, "element 'face' has no list property vertex_indices");
        if (!isIntegerType(element.properties[indexProperty].type))
            throwFileError(file_, "face vertex_indices must have an integer item type");
        scene.triangles.reserve(safeReserve(reader, element));
        std::vector<uint32_t> polygon;
        for (; item < element.count; ++item) {
            for (size_t p = 0; p < element.properties.size(); ++p) {
                const PlyProperty& property = element.properties[p];
                if (static_cast<int>(p) != indexProperty) {
                    if (property.isList) {
                        const int64_t count = readListCount(reader, property);
                        for (int64_t i = 0; i < count; ++i) reader.readNumber(property.type);
                    } else {
                        reader.readNumber(property.type);
                    }
                    continue;
                }
                const int64_t count = readListCount(reader, property);
                polygon.clear();
                for (int64_t i = 0; i < count; ++i) {
                    const int64_t index = reader.readInteger(property.type);
                    if (index < 0 || static_cast<uint64_t>(index) >= vertexCount_)
                        throwFileError(file_, "face " + std::to_string(item) + " has vertex index " + std::to_string(index) +
                                                  " out of range (" + std::to_string(vertexCount_) + " vertices)");
                    polygon.push_back(static_cast<uint32_t>(index));
                }
                if (polygon.size() < 3) ++degenerateFaces_; // a point or an edge: no area
                for (size_t k = 1; k + 1 < polygon.size(); ++k)
                    scene.triangles.emplace_back(polygon[0], polygon[k], polygon[k + 1]);
            }
            if ((item & 0xFFFF) == 0) progress_.update(doneBefore + item);
        }
    }

    const PlyHeader& header_;
    const std::filesystem::path& file_;
    Progress& progress_;
    uint64_t vertexCount_ = 0;
    uint64_t degenerateFaces_ = 0;
};

} // namespace

Scene loadPly(const std::filesystem::path& file, Progress& progress) {
    const std::string bytes = detail::readWholeFile(file);
    const PlyHeader header = parseHeader(bytes, file);
    Scene scene;
    PlyDecoder decoder(header, file, progress);
    const char* data = bytes.data() + header.dataOffset;
    const char* end = bytes.data() + bytes.size();
    if (header.format == PlyFormat::Ascii) {
        const size_t headerLines = static_cast<size_t>(std::count(bytes.data(), data, '\n'));
        AsciiReader reader(data, end, headerLines + 1);
        decoder.decode(reader, scene);
    } else {
        BinaryReader reader(data, end, header.format == PlyFormat::BinaryBigEndian);
        decoder.decode(reader, scene);
    }
    scene.stats.degenerateTrianglesDropped += decoder.degenerateFaces();
    detail::finishLoadedScene(scene, file);
    return scene;
}

} // namespace chcrt
