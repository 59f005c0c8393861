// The "tensor file" container of Mitsuba and the RGL material database (the measured BRDFs of
// materials/measured_bsdf.h are stored in it): named arrays of a fixed element type and shape.
//
//   "tensor_file\0" (12 bytes), version 1 0 (2 bytes), field count (u32), then per field:
//   name length (u16), name, rank (u16), element type (u8: 1-8 integers u8 i8 u16 i16 u32 i32 u64 i64,
//   9-11 floats f16 f32 f64), data offset from the file's start (u64), the extent of each dimension (u64).
//
// All little-endian. Read from memory with every size and offset checked against the file: a field
// whose data would lie outside it, a rank above 16, an unknown type, a repeated name or a truncated
// header is an InputError naming the file and the field. Memory is bounded by the file: a field is a
// view of the bytes it was read from.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

enum class TensorType : uint8_t {
    UInt8 = 1,
    Int8,
    UInt16,
    Int16,
    UInt32,
    Int32,
    UInt64,
    Int64,
    Float16,
    Float32,
    Float64
};

struct TensorField {
    std::string name;
    TensorType type = TensorType::UInt8;
    std::vector<uint64_t> shape;
    std::string_view bytes;  // the data, within the file's bytes

    uint64_t elementCount() const;
};

class TensorFile {
public:
    // Parses `bytes` (which must outlive the result); `fileName` names it in errors.
    TensorFile(std::string_view bytes, std::string fileName);

    const std::string& fileName() const { return fileName_; }
    const std::vector<TensorField>& fields() const { return fields_; }
    // The field `name`, or nullptr.
    const TensorField* find(std::string_view name) const;
    // The field `name` of type `type` and rank `rank`; an InputError otherwise ("the field "ndf" is
    // missing" / "has rank 3, expected 2" / "holds uint8 values, expected float32").
    const TensorField& require(std::string_view name, TensorType type, size_t rank) const;
    // The values of a float32 field (require()d first), in file order.
    std::vector<float> floats(const TensorField& field) const;

    [[noreturn]] void fail(const std::string& message) const;

private:
    std::string fileName_;
    std::vector<TensorField> fields_;
};

const char* tensorTypeName(TensorType type);

}  // namespace penumbra
