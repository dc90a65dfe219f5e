// The output helper (io/output_path.h) and the atomic writer (io/atomic_file.h) on their own: what is refused
// before any work, what a symbolic link does, which permissions a written file gets, and that nothing
// temporary is left in the folder on success or failure. The verbs' use of them: tests/cli/outputs_cli.sh.
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <set>

#include "io/atomic_file.h"
#include "io/output_path.h"
#include "megavox/error.h"
#include "test_support.h"

namespace mv::test {
namespace {

namespace fs = std::filesystem;
using io::OutputKind;
using io::OutputRequest;

class OutputPath : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = temp_path("output_path");
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string at(const std::string& name) const { return dir_ + "/" + name; }
  void put(const std::string& name, const std::string& bytes) const { std::ofstream(at(name)) << bytes; }
  std::string read(const std::string& name) const {
    std::ifstream in(at(name));
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  std::set<std::string> names() const {
    std::set<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.insert(e.path().filename().string());
    return out;
  }
  // The message resolve_output throws for `r` ("" when it accepts it).
  static std::string refusal(const OutputRequest& r) {
    try {
      io::resolve_output(r);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  }
  std::string dir_;
};

TEST_F(OutputPath, RefusesInputsThroughLinksAndHardLinks) {
  put("in.mvx", "x");
  fs::create_symlink("in.mvx", at("soft.mvx"));
  fs::create_hard_link(at("in.mvx"), at("hard.mvx"));
  for (const char* out : {"in.mvx", "soft.mvx", "hard.mvx"})
    EXPECT_NE(refusal({at(out), OutputKind::kFile, "mvx", {at("in.mvx")}}).find("is the input"), std::string::npos)
        << out;
  EXPECT_EQ(refusal({at("other.mvx"), OutputKind::kFile, "mvx", {at("in.mvx")}}), "");
  // A folder output replaced whole may not hold an input.
  fs::create_directories(at("tiles/sub"));
  put("tiles/sub/cloud.ply", "x");
  EXPECT_NE(refusal({at("tiles"), OutputKind::kFolder, "", {at("tiles/sub/cloud.ply")}}).find("holds the input"),
            std::string::npos);
  EXPECT_EQ(refusal({at("tiles2"), OutputKind::kFolder, "", {at("tiles/sub/cloud.ply")}}), "");
}

TEST_F(OutputPath, RefusesWhatIsNotARegularFile) {
  ASSERT_EQ(::mkfifo(at("fifo.mvx").c_str(), 0644), 0);
  EXPECT_NE(refusal({at("fifo.mvx")}).find("FIFO"), std::string::npos);
  fs::create_directories(at("folder.mvx"));
  EXPECT_NE(refusal({at("folder.mvx")}).find("folder"), std::string::npos);
  EXPECT_NE(refusal({"/dev/null"}).find("/dev"), std::string::npos);
  EXPECT_NE(refusal({"/dev/stdout"}).find("/dev"), std::string::npos);
  EXPECT_NE(refusal({"/proc/self/fd/1"}).find("/proc"), std::string::npos);
  fs::create_symlink("/dev/null", at("null_link.mvx"));
  EXPECT_NE(refusal({at("null_link.mvx")}).find("/dev"), std::string::npos);
  put("plain.mvx", "x");
  EXPECT_NE(refusal({at("plain.mvx"), OutputKind::kFolder}).find("not a folder"), std::string::npos);
  EXPECT_NE(refusal({at("x.mvx/")}).find("names a folder"), std::string::npos);
  EXPECT_TRUE(fs::is_fifo(at("fifo.mvx")));
}

TEST_F(OutputPath, FoldersMustExistAndBeFolders) {
  put("file", "x");
  EXPECT_NE(refusal({at("none/x.mvx")}).find("does not exist"), std::string::npos);
  EXPECT_NE(refusal({at("file/x.mvx")}).find("is a file"), std::string::npos);
  EXPECT_NO_THROW(io::check_output_folder(at("new/deeper")));  // made later, where its parent allows
  EXPECT_THROW(io::check_output_folder(at("file/masks")), Error);
  EXPECT_THROW(io::check_output_folder(at("file")), Error);
  EXPECT_EQ(names(), std::set<std::string>{"file"});  // checking makes nothing
}

TEST_F(OutputPath, ExtensionsNoClobberAndFreeSpace) {
  EXPECT_NE(refusal({at("l.mvx"), OutputKind::kFile, "vdb"}).find("name it with .vdb"), std::string::npos);
  EXPECT_EQ(refusal({at("l.vdb"), OutputKind::kFile, "vdb"}), "");
  EXPECT_EQ(refusal({at("l.VDB"), OutputKind::kFile, "vdb"}), "");
  EXPECT_EQ(refusal({at("l.data"), OutputKind::kFile, "vdb"}), "");  // a name megavox does not know: the user's
  EXPECT_EQ(io::format_of_extension("a.JPG"), "jpeg");
  put("old.png", "x");
  EXPECT_NE(refusal({at("old.png"), OutputKind::kFile, "png", {}, 0, true}).find("replacing outputs was refused"),
            std::string::npos);
  EXPECT_EQ(refusal({at("old.png"), OutputKind::kFile, "png", {}, 0, false}), "");
  EXPECT_NE(refusal({at("huge.png"), OutputKind::kFile, "png", {}, uint64_t{1} << 62}).find("free"),
            std::string::npos);
}

TEST_F(OutputPath, LinksAreWrittenThrough) {
  put("target.mvx", "old");
  fs::create_symlink("target.mvx", at("link.mvx"));
  fs::create_symlink("link.mvx", at("link2.mvx"));
  fs::create_symlink("absent.mvx", at("dangling.mvx"));
  EXPECT_EQ(io::resolve_output({at("link2.mvx")}), at("target.mvx"));
  io::write_atomically(at("link2.mvx"), [](std::FILE* f) { return std::fputs("new", f) >= 0; });
  EXPECT_TRUE(fs::is_symlink(at("link.mvx")));
  EXPECT_TRUE(fs::is_symlink(at("link2.mvx")));
  EXPECT_EQ(read("target.mvx"), "new");
  io::write_atomically(at("dangling.mvx"), [](std::FILE* f) { return std::fputs("made", f) >= 0; });
  EXPECT_TRUE(fs::is_symlink(at("dangling.mvx")));
  EXPECT_EQ(read("absent.mvx"), "made");
  fs::create_symlink("loop.mvx", at("loop.mvx"));
  EXPECT_NE(refusal({at("loop.mvx")}).find("symbolic links"), std::string::npos);
}

TEST_F(OutputPath, UmaskForNewFilesAndOldPermissionsForReplacedOnes) {
  const mode_t old = ::umask(027);
  io::write_atomically(at("new.bin"), [](std::FILE* f) { return std::fputs("a", f) >= 0; });
  ::umask(old);
  EXPECT_EQ(fs::status(at("new.bin")).permissions(),
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  fs::permissions(at("new.bin"), fs::perms::owner_read | fs::perms::owner_write);
  io::write_atomically(at("new.bin"), [](std::FILE* f) { return std::fputs("b", f) >= 0; });
  EXPECT_EQ(fs::status(at("new.bin")).permissions(), fs::perms::owner_read | fs::perms::owner_write);
  EXPECT_EQ(read("new.bin"), "b");
}

TEST_F(OutputPath, NothingTemporaryIsLeft) {
  put("keep.bin", "kept");
  EXPECT_THROW(io::write_atomically(at("keep.bin"),
                                    [](std::FILE* f) {
                                      std::fputs("half", f);
                                      errno = ENOSPC;
                                      return false;
                                    }),
               Error);
  EXPECT_EQ(read("keep.bin"), "kept");
  EXPECT_THROW(io::write_atomically_by_name(at("named.vdb"), [](const std::string&) { throw Error("writer failed"); }),
               Error);
  // A writer that opens the file by name (OpenVDB's way) writes the unnamed file through its name.
  io::write_atomically_by_name(at("named.vdb"), [](const std::string& tmp) { std::ofstream(tmp) << "by name"; });
  EXPECT_EQ(read("named.vdb"), "by name");
  EXPECT_EQ(names(), (std::set<std::string>{"keep.bin", "named.vdb"}));
}

}  // namespace
}  // namespace mv::test
