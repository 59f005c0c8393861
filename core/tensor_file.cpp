#include "core/tensor_file.h"

#include <fmt/format.h>

#include <bit>
#include <cstring>

#include "core/error.h"

namespace penumbra {

static_assert(std::endian::native == std::endian::little, "tensor files are little-endian, read in place");

namespace {

constexpr size_t kMaxRank = 16;

uint64_t elementBytes(TensorType type) {
    switch (type) {
        case TensorType::UInt8:
        case TensorType::Int8:
            return 1;
        case TensorType::UInt16:
        case TensorType::Int16:
        case TensorType::Float16:
            return 2;
        case TensorType::UInt32:
        case TensorType::Int32:
        case TensorType::Float32:
            return 4;
        case TensorType::UInt64:
        case TensorType::Int64:
        case TensorType::Float64:
            return 8;
    }
    return 0;
}

// Reads the header front to back, every read bounded by the bytes left.
class HeaderReader {
public:
    HeaderReader(std::string_view bytes, const TensorFile& file) : bytes_(bytes), file_(file) {}

    template <typename T>
    T read(const char* what) {
        if (bytes_.size() - position_ < sizeof(T))
            file_.fail(fmt::format("the header ends within {} (at byte {}): the file is truncated", what,
                                   position_));
        T value;
        std::memcpy(&value, bytes_.data() + position_, sizeof(T));
        position_ += sizeof(T);
        return value;
    }
    std::string_view readBytes(size_t count, const char* what) {
        if (bytes_.size() - position_ < count)
            file_.fail(fmt::format("the header ends within {} (at byte {}): the file is truncated", what,
                                   position_));
        const std::string_view out = bytes_.substr(position_, count);
        position_ += count;
        return out;
    }

private:
    std::string_view bytes_;
    const TensorFile& file_;
    size_t position_ = 0;
};

}  // namespace

const char* tensorTypeName(TensorType type) {
    static constexpr const char* kNames[] = {"uint8",  "int8",  "uint16",  "int16",   "uint32", "int32",
                                             "uint64", "int64", "float16", "float32", "float64"};
    const int index = int(type) - 1;
    return index >= 0 && index < 11 ? kNames[index] : "an unknown type";
}

uint64_t TensorField::elementCount() const {
    uint64_t count = 1;
    for (uint64_t extent : shape) count *= extent;  // bounded by the file's size (checked when read)
    return count;
}

TensorFile::TensorFile(std::string_view bytes, std::string fileName) : fileName_(std::move(fileName)) {
    HeaderReader header(bytes, *this);
    static constexpr char kMagic[12] = {'t', 'e', 'n', 's', 'o', 'r', '_', 'f', 'i', 'l', 'e', '\0'};
    if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
        fail(
            "not a tensor file: it does not start with \"tensor_file\" (a measured BRDF of the RGL database, "
            "a .bsdf file)");
    header.readBytes(sizeof kMagic, "the magic bytes");
    const auto major = header.read<uint8_t>("the version"), minor = header.read<uint8_t>("the version");
    if (major != 1 || minor != 0)
        fail(fmt::format("tensor file version {}.{}: only version 1.0 is read", major, minor));
    const auto count = header.read<uint32_t>("the field count");
    for (uint32_t f = 0; f < count; ++f) {
        TensorField field;
        const auto nameLength = header.read<uint16_t>("a field's name");
        field.name = std::string(header.readBytes(nameLength, "a field's name"));
        const std::string label = fmt::format("field {} (\"{}\")", f, field.name);
        const auto rank = header.read<uint16_t>("a field's rank");
        if (rank > kMaxRank) fail(fmt::format("{} has rank {}: at most {} is read", label, rank, kMaxRank));
        const auto type = header.read<uint8_t>("a field's type");
        if (type < 1 || type > 11) fail(fmt::format("{} has element type {}: expected 1 to 11", label, type));
        field.type = TensorType(type);
        const auto offset = header.read<uint64_t>("a field's offset");
        // The size so far never exceeds the file's, so the product cannot overflow.
        uint64_t size = elementBytes(field.type);
        for (uint16_t d = 0; d < rank; ++d) {
            const auto extent = header.read<uint64_t>("a field's shape");
            field.shape.push_back(extent);
            if (extent != 0 && size > bytes.size() / extent)
                fail(fmt::format("{} holds more data than the file ({} bytes)", label, bytes.size()));
            size *= extent;
        }
        if (offset > bytes.size() || size > bytes.size() - offset)
            fail(fmt::format("{} lies outside the file: {} bytes at offset {}, the file has {}", label, size,
                             offset, bytes.size()));
        if (find(field.name)) fail(fmt::format("{}: the name is used twice", label));
        field.bytes = bytes.substr(offset, size);
        fields_.push_back(std::move(field));
    }
}

const TensorField* TensorFile::find(std::string_view name) const {
    for (const TensorField& field : fields_)
        if (field.name == name) return &field;
    return nullptr;
}

const TensorField& TensorFile::require(std::string_view name, TensorType type, size_t rank) const {
    const TensorField* field = find(name);
    if (!field) fail(fmt::format("the field \"{}\" is missing", name));
    if (field->shape.size() != rank)
        fail(fmt::format("the field \"{}\" has rank {}, expected {}", name, field->shape.size(), rank));
    if (field->type != type)
        fail(fmt::format("the field \"{}\" holds {} values, expected {}", name, tensorTypeName(field->type),
                         tensorTypeName(type)));
    return *field;
}

std::vector<float> TensorFile::floats(const TensorField& field) const {
    if (field.type != TensorType::Float32)
        fail(fmt::format("the field \"{}\" does not hold float32 values", field.name));
    std::vector<float> out(field.bytes.size() / sizeof(float));
    if (!out.empty()) std::memcpy(out.data(), field.bytes.data(), out.size() * sizeof(float));
    return out;
}

void TensorFile::fail(const std::string& message) const { throwFileError(fileName_, message); }

}  // namespace penumbra
