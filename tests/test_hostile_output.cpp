// Hostile outputs: no file but the output is ever destroyed, and a failed command changes
// no output. An output is only ever a regular file or a new name; temporaries are this
// process's own (O_TMPFILE or O_EXCL) and only those are removed; several outputs are
// replaced all-or-nothing; long names fit NAME_MAX.
#include <doctest/doctest.h>

#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "softpbr/image/write.h"

namespace fs = std::filesystem;
namespace image = softpbr::image;

namespace {

// A fresh folder under the system's temporary folder, removed at the end of the test.
struct Folder {
  fs::path path;
  Folder() {
    path = fs::temp_directory_path() / ("softpbr-hostile-output-" + std::to_string(::getpid()) + "-" +
                                        std::to_string(counter()++));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~Folder() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
  static int& counter() {
    static int n = 0;
    return n;
  }
};

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write(const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; }

std::vector<std::uint8_t> bytes(const std::string& s) { return {s.begin(), s.end()}; }

std::vector<std::string> names(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

std::string error_of(const fs::path& p, const std::string& text) {
  try {
    image::write_file_atomic(p, bytes(text));
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("an output replaces a regular file or creates a new name, and nothing else") {
  Folder f;
  const fs::path file = f.path / "out.png";
  CHECK(error_of(file, "one") == "");
  CHECK(read(file) == "one");
  CHECK(error_of(file, "two") == "");
  CHECK(read(file) == "two");
  CHECK(names(f.path) == std::vector<std::string>{"out.png"});  // no temporary left

  // A named pipe: refused without opening it (opening would block), and still a pipe.
  const fs::path fifo = f.path / "fifo.png";
  REQUIRE(::mkfifo(fifo.c_str(), 0644) == 0);
  CHECK(error_of(fifo, "x") == fifo.string() + ": cannot write: it is a named pipe, not a regular file (an output is a regular file or a new name)");
  CHECK(fs::is_fifo(fifo));
  // A symbolic link (to a regular file): the link would be replaced, not its target.
  const fs::path link = f.path / "link.png";
  fs::create_symlink(file, link);
  CHECK(error_of(link, "x").find("cannot write: it is a symbolic link") != std::string::npos);
  CHECK(fs::is_symlink(link));
  CHECK(read(file) == "two");
  // A folder.
  fs::create_directory(f.path / "dir.png");
  CHECK(error_of(f.path / "dir.png", "x") == (f.path / "dir.png").string() + ": cannot write: it is a folder");
  // A character device: /dev/null exists on every test machine; a node of our own where we may.
  CHECK(error_of("/dev/null", "x") == "/dev/null: cannot write: it is a character device, not a regular file (an output is a regular file or a new name)");
  struct stat st {};
  REQUIRE(::stat("/dev/null", &st) == 0);
  CHECK(S_ISCHR(st.st_mode));
  if (::geteuid() == 0) {
    const fs::path node = f.path / "node.png";
    REQUIRE(::mknod(node.c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0);
    CHECK(error_of(node, "x").find("cannot write: it is a character device") != std::string::npos);
    REQUIRE(::lstat(node.c_str(), &st) == 0);
    CHECK(S_ISCHR(st.st_mode));
  }
  // A missing folder names the output, not a temporary.
  CHECK(error_of(f.path / "no" / "such" / "x.png", "x") ==
        (f.path / "no" / "such" / "x.png").string() + ": cannot write: the folder " + (f.path / "no" / "such").string() +
            " does not exist");
  // A file where the folder should be ("-o file/x.png") is that, not a missing folder
  // (it was "the folder file does not exist"); so is a link loop.
  write(f.path / "file", "a file");
  CHECK(error_of(f.path / "file" / "x.png", "x") ==
        (f.path / "file" / "x.png").string() + ": cannot write: " + (f.path / "file").string() + " is not a folder");
  CHECK(error_of(f.path / "file" / "deeper" / "x.png", "x") == (f.path / "file" / "deeper" / "x.png").string() +
                                                                   ": cannot write: a part of " +
                                                                   (f.path / "file" / "deeper").string() + " is not a folder");
  fs::create_symlink("loop", f.path / "loop");
  CHECK(error_of(f.path / "loop" / "x.png", "x") == (f.path / "loop" / "x.png").string() + ": cannot write: the folder " +
                                                        (f.path / "loop").string() +
                                                        ": too many levels of symbolic links (a link loop)");
}

TEST_CASE("files that merely look like temporaries are never removed, and two writers of one name both succeed") {
  Folder f;
  const fs::path out = f.path / "new.png";
  for (const char* lookalike : {".new.png.tmpl", ".new.png.tmp12345", ".new.png.tmp-abcdefghij"}) write(f.path / lookalike, "mine");
  CHECK(error_of(out, "image") == "");
  CHECK(names(f.path) == std::vector<std::string>{".new.png.tmp-abcdefghij", ".new.png.tmp12345", ".new.png.tmpl", "new.png"});
  for (const char* lookalike : {".new.png.tmpl", ".new.png.tmp12345", ".new.png.tmp-abcdefghij"})
    CHECK(read(f.path / lookalike) == "mine");

  // Writers racing on one name: every write succeeds, the file is always one whole write.
  const std::string a(100000, 'a'), b(100000, 'b');
  std::vector<std::thread> writers;
  std::vector<std::string> errors(8);
  for (int t = 0; t < 8; ++t)
    writers.emplace_back([&, t] {
      for (int i = 0; i < 20 && errors[t].empty(); ++i) errors[t] = error_of(f.path / "race.png", t % 2 ? a : b);
    });
  for (std::thread& t : writers) t.join();
  for (const std::string& e : errors) CHECK(e == "");
  const std::string last = read(f.path / "race.png");
  CHECK((last == a || last == b));
  CHECK(names(f.path).size() == 5);  // the three look-alikes, new.png and race.png
}

TEST_CASE("several outputs are all-or-nothing: a write that fails replaces none of them") {
  Folder f;
  write(f.path / "keep.png", "KEEP");
  write(f.path / "big.exr", "OLD");
  // A file size limit stands in for a full disk: the second file cannot be written whole.
  std::signal(SIGXFSZ, SIG_IGN);
  rlimit old{};
  REQUIRE(::getrlimit(RLIMIT_FSIZE, &old) == 0);
  rlimit limited = old;
  limited.rlim_cur = 4096;
  REQUIRE(::setrlimit(RLIMIT_FSIZE, &limited) == 0);
  std::string error;
  {
    image::OutputFiles outputs;
    try {
      outputs.add(f.path / "keep.png", bytes("new png"));
      outputs.add(f.path / "big.exr", bytes(std::string(100000, 'x')));
      outputs.commit();
    } catch (const std::runtime_error& e) {
      error = e.what();
    }
  }
  REQUIRE(::setrlimit(RLIMIT_FSIZE, &old) == 0);
  std::signal(SIGXFSZ, SIG_DFL);
  CHECK(error == (f.path / "big.exr").string() + ": write failed (disk full?)");
  CHECK(read(f.path / "keep.png") == "KEEP");
  CHECK(read(f.path / "big.exr") == "OLD");
  CHECK(names(f.path) == std::vector<std::string>{"big.exr", "keep.png"});  // temporaries removed

  // Discarded before commit: nothing replaced, nothing left.
  {
    image::OutputFiles outputs;
    outputs.add(f.path / "keep.png", bytes("new"));
  }
  CHECK(read(f.path / "keep.png") == "KEEP");
  CHECK(names(f.path) == std::vector<std::string>{"big.exr", "keep.png"});

  // A destination that became a folder between add() and commit(): refused, none replaced.
  {
    image::OutputFiles outputs;
    outputs.add(f.path / "keep.png", bytes("new"));
    outputs.add(f.path / "late.png", bytes("new"));
    fs::create_directory(f.path / "late.png");
    CHECK_THROWS_WITH(outputs.commit(), ((f.path / "late.png").string() + ": cannot write: it is a folder").c_str());
  }
  CHECK(read(f.path / "keep.png") == "KEEP");
  CHECK(names(f.path) == std::vector<std::string>{"big.exr", "keep.png", "late.png"});
}

TEST_CASE("a name of NAME_MAX bytes is written (its temporary fits too), one byte more is refused before writing") {
  Folder f;
  const long max = ::pathconf(f.path.c_str(), _PC_NAME_MAX);
  REQUIRE(max > 8);
  const std::string longest = std::string(static_cast<std::size_t>(max) - 4, 'n') + ".png";
  CHECK(error_of(f.path / longest, "ok") == "");
  CHECK(read(f.path / longest) == "ok");
  const std::string over = "n" + longest;
  CHECK(image::output_problem(f.path / over) == "cannot write: the file name is " + std::to_string(max + 1) +
                                                     " bytes, over the limit of " + std::to_string(max) + " of its folder");
  CHECK(error_of(f.path / over, "x").find("over the limit") != std::string::npos);
  CHECK(names(f.path) == std::vector<std::string>{longest});
}
