// io::FileStreambuf (io/file_streambuf.h), the std::istream OpenVDB reads through: reads and seeks as a
// std::ifstream of the same file would, across its 64 KiB blocks, and passes a read fault on as mv::Error.
#include <gtest/gtest.h>

#include <cstdio>
#include <istream>
#include <string>
#include <vector>

#include "io/file_ops.h"
#include "io/file_streambuf.h"
#include "megavox/error.h"
#include "test_support.h"

namespace mv::test {
namespace {

// A file of `n` bytes whose byte i is (i * 7 + i / 251) mod 256: no two nearby blocks alike.
std::string streambuf_fixture(size_t n) {
  const std::string path = temp_path("streambuf.bin");
  std::vector<char> bytes(n);
  for (size_t i = 0; i < n; ++i) bytes[i] = static_cast<char>((i * 7 + i / 251) & 0xff);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  std::fwrite(bytes.data(), 1, n, f);
  std::fclose(f);
  return path;
}

char streambuf_byte(size_t i) { return static_cast<char>((i * 7 + i / 251) & 0xff); }

TEST(FileStreambuf, ReadsAndSeeksAsTheFile) {
  const size_t n = 200000;  // three whole blocks and a part
  const std::string path = streambuf_fixture(n);
  io::FileStreambuf buf(path);
  std::istream is(&buf);
  std::vector<char> got(n);
  ASSERT_TRUE(is.read(got.data(), 100000));
  for (size_t i = 0; i < 100000; ++i) ASSERT_EQ(got[i], streambuf_byte(i)) << i;
  EXPECT_EQ(is.tellg(), std::streampos(100000));
  // back inside the block read last, back to an earlier block, forward past it, relative, from the end
  for (const std::streamoff at : {std::streamoff{99000}, std::streamoff{10}, std::streamoff{150001}}) {
    is.seekg(at);
    EXPECT_EQ(is.tellg(), std::streampos(at));
    char c[3];
    ASSERT_TRUE(is.read(c, 3));
    for (int k = 0; k < 3; ++k) EXPECT_EQ(c[k], streambuf_byte(static_cast<size_t>(at) + k)) << at;
  }
  is.seekg(-5, std::ios_base::cur);
  EXPECT_EQ(is.tellg(), std::streampos(149999));
  is.seekg(-2, std::ios_base::end);
  EXPECT_EQ(is.tellg(), std::streampos(n - 2));
  char tail[4];
  is.read(tail, 4);  // only two bytes are left
  EXPECT_EQ(is.gcount(), 2);
  EXPECT_EQ(tail[1], streambuf_byte(n - 1));
  EXPECT_TRUE(is.eof());
  std::remove(path.c_str());
}

TEST(FileStreambuf, AReadFaultIsAnErrorNamingTheFile) {
  const std::string path = streambuf_fixture(100000);
  io::FileStreambuf buf(path);
  std::istream is(&buf);
  is.exceptions(std::ios::failbit | std::ios::badbit);
  char c[10];
  is.read(c, 10);
  io::faults::arm(io::faults::Kind::kReadError, 0);  // the next read: the second block
  std::vector<char> rest(99990);
  try {
    is.read(rest.data(), static_cast<std::streamsize>(rest.size()));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": read error"), std::string::npos) << e.what();
  }
  io::faults::disarm();
  EXPECT_THROW(io::FileStreambuf(path + ".missing"), Error);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace mv::test
