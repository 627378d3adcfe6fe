// Input files given by path (scenes, meshes, checkpoints, trajectories, probes): a directory, a
// FIFO or a device is refused as what it is, before anything is opened or read, so no reader
// blocks on a FIFO without a writer or reads /dev/zero forever.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <filesystem>
#include <string>

#include "solver/io/checkpoint.hpp"
#include "solver/io/input_files.hpp"
#include "solver/io/probes.hpp"
#include "solver/io/trajectory.hpp"
#include "tests/support/test_files.hpp"

namespace talus {
namespace {

// The message of the std::runtime_error `call` throws, or a marker that it threw none.
template <class Call>
std::string error_of(Call call) {
  try {
    call();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "<no exception>";
}

struct Specials {
  std::string dir, file, folder, fifo, missing;
};

Specials make_specials(const std::string& name) {
  Specials s;
  s.dir = talus_test::fresh_test_directory("test-io", name);
  s.file = talus_test::write_text(s.dir + "/plain.txt", "two\nlines\n");
  s.folder = s.dir + "/folder";
  std::filesystem::create_directory(s.folder);
  s.fifo = s.dir + "/pipe";
  EXPECT_EQ(::mkfifo(s.fifo.c_str(), 0600), 0);
  s.missing = s.dir + "/missing";
  return s;
}

}  // namespace

TEST(InputFiles, EachKindOfPathIsNamed) {
  const Specials s = make_specials("input_kinds");
  EXPECT_EQ(input_file_problem(s.file), "");
  EXPECT_EQ(input_file_problem(s.folder), "is a directory, not a regular file");
  EXPECT_EQ(input_file_problem(s.fifo), "is a FIFO (named pipe), not a regular file");
  EXPECT_EQ(input_file_problem("/dev/zero"), "is a character device, not a regular file");
  EXPECT_EQ(input_file_problem(s.missing), "does not exist");
  // A symbolic link is followed: to a file it reads, to a FIFO it is refused as the FIFO.
  std::filesystem::create_symlink(s.file, s.dir + "/to_file");
  std::filesystem::create_symlink(s.fifo, s.dir + "/to_fifo");
  EXPECT_EQ(read_input_file(s.dir + "/to_file"), "two\nlines\n");
  EXPECT_EQ(input_file_problem(s.dir + "/to_fifo"), "is a FIFO (named pipe), not a regular file");
  // A path through a regular file is not a missing file but a wrong one, and the file is named.
  EXPECT_EQ(input_file_problem(s.file + "/inside"),
            "cannot be reached: '" + s.file + "' on its path is not a directory");
  EXPECT_EQ(input_file_problem(s.file + "/"),
            "cannot be reached: '" + s.file + "' on its path is not a directory");
}

TEST(InputFiles, ReadInputFileRefusesWithoutReadingAndCarriesTheProblem) {
  const Specials s = make_specials("input_read");
  EXPECT_EQ(read_input_file(s.file), "two\nlines\n");
  EXPECT_EQ(error_of([&] { read_input_file("/dev/zero"); }),
            "/dev/zero: is a character device, not a regular file");
  try {
    read_input_file(s.fifo);  // would block in open(2) if it were opened for reading
    ADD_FAILURE() << "read a FIFO";
  } catch (const InputFileError& e) {
    EXPECT_EQ(e.what(), s.fifo + ": is a FIFO (named pipe), not a regular file");
    EXPECT_EQ(e.problem(), "is a FIFO (named pipe), not a regular file");
  }
  EXPECT_EQ(error_of([&] { read_input_file(s.folder); }),
            s.folder + ": is a directory, not a regular file");
  EXPECT_EQ(error_of([&] { read_input_file(s.missing); }), s.missing + ": does not exist");
}

TEST(InputFiles, CheckpointTrajectoryAndProbeReadersUseIt) {
  const Specials s = make_specials("input_readers");
  EXPECT_EQ(error_of([&] { read_checkpoint(s.fifo); }),
            s.fifo + ": cannot read the checkpoint: it is a FIFO (named pipe), not a regular file");
  EXPECT_EQ(error_of([&] { read_checkpoint(s.folder); }),
            s.folder + ": cannot read the checkpoint: it is a directory, not a regular file");
  EXPECT_EQ(error_of([&] { file_hash("/dev/zero"); }),
            "/dev/zero: is a character device, not a regular file");
  EXPECT_EQ(error_of([&] { read_probe_file(s.fifo); }),
            s.fifo + ": is a FIFO (named pipe), not a regular file");
  // A frame name on a FIFO, in both formats: HDF5 would open it as readily as a file.
  for (const std::string name : {"trajectory_000000001.csv", "trajectory_000000002.h5"}) {
    const std::string frame = s.dir + "/" + name;
    ASSERT_EQ(::mkfifo(frame.c_str(), 0600), 0);
    EXPECT_EQ(error_of([&] { read_trajectory_frame(frame); }),
              frame + ": is a FIFO (named pipe), not a regular file");
  }
  EXPECT_EQ(error_of([&] { read_run_info(s.folder); }),
            s.folder +
                "/run.json: does not exist (expected the run.json that talus run writes "
                "beside its trajectory frames)");
}

TEST(InputFiles, ShownInputEscapesBadBytesAndCutsLongText) {
  // Printable ASCII and valid UTF-8 as they are; a control byte, a C1 control (U+0085) and bytes
  // that are not UTF-8 as \xNN.
  EXPECT_EQ(shown_input(std::string("a\x1b[2Jb\xC3\xA9\xC2\x85\xFF\0", 12)),
            "a\\x1B[2Jb\xC3\xA9\\xC2\\x85\\xFF\\x00");
  EXPECT_EQ(shown_input("\xED\xA0\x80"), "\\xED\\xA0\\x80");  // a UTF-16 surrogate
  EXPECT_EQ(shown_input(std::string(100, 'x'), 10), "xxxxxxxxxx... (100 bytes)");
  EXPECT_EQ(shown_input(std::string(10, 'x'), 10), "xxxxxxxxxx");
}

}  // namespace talus
