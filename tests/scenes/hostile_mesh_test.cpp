// Hostile mesh files (tests/data/hostile): each once crashed, hung or rendered garbage silently.
// Every one must now be refused with an InputError naming the file, and the line where the
// validator knows it.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>

#include "scenes/mesh_import.h"
#include "tests/support/expect_input_error.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using testing::catchInputError;

const fs::path kHostile = fs::path(PENUMBRA_TEST_DATA_DIR) / "hostile";

// tinyobjloader ends a line at a lone CR, so "#\rf 1 2 4" holds a face; the validator must see it.
TEST(HostileMesh, ObjFaceHiddenBehindLoneCarriageReturn) {
    const InputError e = catchInputError([] { importMesh(kHostile / "cr_hidden_face.obj"); });
    EXPECT_EQ(e.where().line, 5);
    EXPECT_CONTAINS(e.what(), "cr_hidden_face.obj:5:");
    EXPECT_CONTAINS(e.what(), "vertex index 4 is out of range: the file has 3 vertices");
}

TEST(HostileMesh, ObjOnlyFaceHiddenBehindLoneCarriageReturn) {
    const InputError e = catchInputError([] { importMesh(kHostile / "cr_only_face.obj"); });
    EXPECT_CONTAINS(e.what(), "cr_only_face.obj:2:");
    EXPECT_CONTAINS(e.what(), "vertex index 1 is out of range: the file has 0 vertices");
}

TEST(HostileMesh, ObjNanVertexHiddenBehindLoneCarriageReturn) {
    const InputError e = catchInputError([] { importMesh(kHostile / "cr_hidden_nan.obj"); });
    EXPECT_CONTAINS(e.what(), "cr_hidden_nan.obj:2:3: vertex 1 has a non-finite coordinate (nan)");
}

TEST(HostileMesh, ObjWithOldMacLineEndingsStillLoads) {
    // Lone CRs are line ends for both the validator and the loader, so a CR-only file is fine.
    const TriangleMesh mesh = importObj("v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r", "mac.obj");
    EXPECT_EQ(mesh.triangleCount(), 1u);
    EXPECT_EQ(mesh.positions.size(), 3u);
}

// assimp ends PLY header lines at LF only; "\rend_header" would end the header for a CR-aware
// validator but not for assimp, which then hung (ASCII) or crashed (binary).
TEST(HostileMesh, PlyAsciiHeaderWithLoneCarriageReturn) {
    const InputError e = catchInputError([] { importMesh(kHostile / "cr_end_header_ascii.ply"); });
    EXPECT_EQ(e.where().line, 9);
    EXPECT_CONTAINS(e.what(), "cr_end_header_ascii.ply:9:1: a carriage return that does not end the line");
}

TEST(HostileMesh, PlyBinaryHeaderWithLoneCarriageReturn) {
    const InputError e = catchInputError([] { importMesh(kHostile / "cr_end_header_binary.ply"); });
    EXPECT_CONTAINS(e.what(), "cr_end_header_binary.ply:9:1: a carriage return that does not end the line");
}

TEST(HostileMesh, PlyHeaderWithCrLfLineEndingsStillLoads) {
    const TriangleMesh mesh = importPly(
        "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\n"
        "property float z\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
        "0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n",
        "crlf.ply");
    EXPECT_EQ(mesh.triangleCount(), 1u);
}

// Found by fuzz/ply_fuzzer: a second 'vertex' element with more vertices than the first. assimp
// 5.2 writes its values past the end of the first one's arrays (valgrind: "Invalid write of size
// 8"; under AddressSanitizer a bad free later), so the header must declare each element once.
TEST(HostileMesh, PlyElementDeclaredTwiceIsRefused) {
    const InputError e = catchInputError([] { importMesh(kHostile / "duplicate_vertex_element.ply"); });
    EXPECT_CONTAINS(e.what(),
                    "duplicate_vertex_element.ply:8:1: the element 'vertex' is declared a second time");
}

// Found by fuzz/ply_fuzzer: an ASCII face index beyond every integer type was converted to one for
// the error message (undefined behaviour); the message now quotes the value as read.
TEST(HostileMesh, PlyFaceIndexBeyondIntegersIsRefused) {
    const InputError e = catchInputError([] { importMesh(kHostile / "face_index_beyond_integers.ply"); });
    EXPECT_CONTAINS(
        e.what(),
        "face 0 (counting from 0) uses vertex 3.3333333333333334e+36, but the file has only 3 vertices");
}

// Found by fuzz/ply_fuzzer: a header that declared 2 billion vertices in a file of a few hundred
// bytes made the reader allocate 25 GB for them before reading a row; rows are counted against
// the bytes after the header first.
TEST(HostileMesh, PlyRowsBeyondWhatTheFileHoldsAreRefusedBeforeAllocating) {
    const InputError e = catchInputError([] { importMesh(kHostile / "vertices_beyond_the_body.ply"); });
    EXPECT_CONTAINS(
        e.what(),
        "vertices_beyond_the_body.ply: the file ends early (truncated?): the element 'vertex' declares "
        "2124695998 rows, which take at least 12748175988 bytes, but the file holds 26 bytes after its "
        "header");
}

// tinyobjloader splits a polygon in time quadratic in its corners (10^5 corners: 45 s), so faces
// have a documented limit of 1024 corners.
TEST(HostileMesh, ObjFaceBeyondTheCornerLimitIsRefused) {
    const InputError e = catchInputError([] { importMesh(kHostile / "face_1025_corners.obj"); });
    EXPECT_CONTAINS(e.what(),
                    "face_1025_corners.obj:4:1: a face with 1025 corners; penumbra takes at most 1024");
}

TEST(HostileMesh, ObjFaceAtTheCornerLimitLoads) {
    EXPECT_EQ(importMesh(kHostile / "face_1024_corners.obj").triangleCount(), 1022u);
}

// Inputs that are not regular files, or too large: once a hang in open() (a FIFO), a read until
// memory ran out (/dev/zero), or an inflation without limit (a small .ply.gz).
class HostileMeshFiles : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("penumbra-hostile-mesh-" +
                std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
};

TEST_F(HostileMeshFiles, FifoIsRefusedWithoutBlocking) {
    const fs::path fifo = dir_ / "pipe.obj";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    const InputError e = catchInputError([&] { importMesh(fifo); });
    EXPECT_CONTAINS(e.what(), "pipe.obj: is a FIFO (named pipe), not a regular file");
}

TEST_F(HostileMeshFiles, DeviceIsRefused) {
    const fs::path zero = dir_ / "zero.obj";
    fs::create_symlink("/dev/zero", zero);
    const InputError e = catchInputError([&] { importMesh(zero); });
    EXPECT_CONTAINS(e.what(), "zero.obj: is a character device, not a regular file");
}

TEST_F(HostileMeshFiles, FileBeyondTheSizeLimitIsRefusedUnread) {
    const fs::path huge = dir_ / "huge.obj";
    std::ofstream(huge).put('v');
    fs::resize_file(huge, (uint64_t(5) << 30));  // sparse: takes no disk space
    const InputError e = catchInputError([&] { importMesh(huge); });
    EXPECT_CONTAINS(e.what(), "huge.obj: the mesh file is 5.0 GiB; penumbra reads at most 4.0 GiB");
}

TEST_F(HostileMeshFiles, GzipInflationIsBounded) {
    // 8 KB of gzip that inflates to 8 MiB; read with a limit of 1 MiB (the default is 4 GiB).
    const InputError e =
        catchInputError([] { importMesh(kHostile / "inflates_to_8mib.ply.gz", uint64_t(1) << 20); });
    EXPECT_CONTAINS(e.what(), "inflates_to_8mib.ply.gz: the mesh file decompresses to more than 1.0 MiB");
}

}  // namespace
}  // namespace penumbra
