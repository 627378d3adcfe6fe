// The bad-input table: every case in tests/bad_input/cases/*.yaml runs the built `talus` binary on
// one bad input (a scene with an edit, a mesh file, an argument, a damaged checkpoint, a path that
// is not a file) and must exit with the case's status and print its message fragment. Beyond
// what each case names, every case is held to what any error must be (the scan, `check_message`):
// one line on stderr that starts "talus: error: ", printable UTF-8, no library internals (`std::`,
// `stoll`, `basic_filebuf`, ...), no doubled location prefix, no input echoed at length, nothing
// on stdout and no output file left behind. The case format is in tests/bad_input/README.md.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "tests/app/run_talus.hpp"

namespace {

namespace fs = std::filesystem;
using talus_test::ProcessResult;
using talus_test::run_talus;

struct Base {
  std::string group, name, scene;
};

struct Case {
  std::string group;  // the cases file's stem
  std::string name;
  std::string scene;  // the scene text (the base with the edits); empty: no scene file
  std::vector<std::pair<std::string, std::string>> files;  // written into the case directory
  std::vector<std::pair<std::string, std::string>> setup;  // (action, path) done before the run
  std::vector<std::string> args;
  int exit_code = 2;
  std::vector<std::string> fragments;  // each must appear in stderr
  std::size_t warnings = 0;            // warning lines allowed before the error
  bool needs_opencv = false;           // `requires: opencv`: skipped where talus has no render
  std::string problem;                 // a malformed case: reported as the test's failure
};

// gtest prints a failing case's parameter: its name, not its bytes.
void PrintTo(const Case& c, std::ostream* os) {
  *os << c.group << "/" << c.name;
}

const std::vector<std::string> kDefaultArgs = {"run", "--quiet", "--output", "{dir}/out",
                                               "{scene}"};

// `text` with its one occurrence of `from` replaced by `to`; a case whose `from` is missing or
// found twice is malformed (an edit that no longer applies must not leave a valid scene).
bool apply_edit(std::string& text, const std::string& from, const std::string& to,
                std::string& problem) {
  const std::size_t at = text.find(from);
  if (at == std::string::npos || text.find(from, at + 1) != std::string::npos) {
    problem = "edit '" + from + "' is " + (at == std::string::npos ? "not in" : "twice in") +
              " the base scene";
    return false;
  }
  text.replace(at, from.size(), to);
  return true;
}

std::vector<std::string> string_list(const YAML::Node& node) {
  std::vector<std::string> out;
  if (node.IsScalar()) out.push_back(node.as<std::string>());
  if (node.IsSequence())
    for (const YAML::Node& n : node) out.push_back(n.as<std::string>());
  return out;
}

std::vector<Base> g_bases;  // every cases file's bases, filled by load_cases

std::vector<Case> load_cases() {
  std::vector<Case> cases;
  std::vector<fs::path> paths;
  for (const auto& entry : fs::directory_iterator(TALUS_SOURCE_DIR "/tests/bad_input/cases"))
    if (entry.path().extension() == ".yaml") paths.push_back(entry.path());
  std::sort(paths.begin(), paths.end());
  for (const fs::path& path : paths) {
    const std::string group = path.stem().string();
    YAML::Node file;
    try {
      file = YAML::LoadFile(path.string());
    } catch (const std::exception& e) {
      Case bad;
      bad.group = group;
      bad.name = "file";
      bad.problem = path.string() + ": " + e.what();
      cases.push_back(bad);
      continue;
    }
    std::map<std::string, std::string> bases;
    for (const auto& base : file["bases"]) {
      bases[base.first.as<std::string>()] = base.second.as<std::string>();
      g_bases.push_back({group, base.first.as<std::string>(), base.second.as<std::string>()});
    }
    for (const YAML::Node& node : file["cases"]) {
      Case c;
      c.group = group;
      try {
        c.name = node["name"].as<std::string>();
        if (node["scene"]) {
          c.scene = node["scene"].as<std::string>();
        } else if (!node["no_scene"] || !node["no_scene"].as<bool>()) {
          const std::string base = node["base"] ? node["base"].as<std::string>() : "default";
          if (!bases.count(base)) c.problem = "no base scene '" + base + "'";
          c.scene = bases[base];
        }
        for (const YAML::Node& edit : node["edits"]) {
          if (!edit.IsSequence() || edit.size() != 2) {
            c.problem = "an edit is [from, to]";
            break;
          }
          if (!apply_edit(c.scene, edit[0].as<std::string>(), edit[1].as<std::string>(), c.problem))
            break;
        }
        if (node["append"]) c.scene += node["append"].as<std::string>();
        for (const auto& f : node["files"])
          c.files.emplace_back(f.first.as<std::string>(), f.second.as<std::string>());
        for (const YAML::Node& s : node["setup"]) {
          const std::string action = s.begin()->first.as<std::string>();
          c.setup.emplace_back(action, s.begin()->second.as<std::string>());
        }
        c.args = node["args"] ? string_list(node["args"]) : kDefaultArgs;
        c.exit_code = node["exit"] ? node["exit"].as<int>() : 2;
        c.fragments = string_list(node["error"]);
        if (c.fragments.empty()) c.problem = "no expected message fragment ('error')";
        c.warnings = node["warnings"] ? node["warnings"].as<std::size_t>() : 0;
        const std::vector<std::string> needs =
            node["requires"] ? string_list(node["requires"]) : std::vector<std::string>{};
        for (const std::string& need : needs) {
          if (need == "opencv")
            c.needs_opencv = true;
          else
            c.problem = "unknown requirement '" + need + "' (known: opencv)";
        }
      } catch (const std::exception& e) {
        c.problem = std::string("malformed case: ") + e.what();
      }
      cases.push_back(c);
    }
  }
  return cases;
}

const std::vector<Case>& all_cases() {
  static const std::vector<Case> cases = load_cases();
  return cases;
}

std::string substitute(std::string text, const std::string& dir, const std::string& scene) {
  for (const auto& [key, value] :
       {std::pair<std::string, std::string>{"{dir}", dir},
        std::pair<std::string, std::string>{"{scene}", scene},
        std::pair<std::string, std::string>{"{source}", TALUS_SOURCE_DIR}}) {
    for (std::size_t at = text.find(key); at != std::string::npos; at = text.find(key, at))
      text.replace(at, key.size(), value), at += value.size();
  }
  return text;
}

// Whether `text` is valid UTF-8 with no control characters but newlines.
bool printable_utf8(const std::string& text) {
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      if ((c < 0x20 && c != '\n') || c == 0x7f) return false;
      ++i;
      continue;
    }
    const int extra = c >= 0xf5 ? -1 : c >= 0xf0 ? 3 : c >= 0xe0 ? 2 : c >= 0xc2 ? 1 : -1;
    if (extra < 0 || i + extra >= text.size()) return false;
    for (int k = 1; k <= extra; ++k)
      if ((static_cast<unsigned char>(text[i + k]) & 0xc0) != 0x80) return false;
    i += extra + 1;
  }
  return true;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// What every error must be, whatever the case: the scan. Returns the failures, empty if none.
std::vector<std::string> check_message(const Case& c, const ProcessResult& r) {
  std::vector<std::string> failures;
  const std::string& err = r.err;
  if (err.empty() || err.back() != '\n') failures.push_back("stderr does not end in a newline");
  if (!printable_utf8(err))
    failures.push_back("stderr holds control characters or bytes that are not UTF-8");
  // Library internals and raw exception texts that say nothing to a user.
  for (const char* internal :
       {"std::",   "basic_",   "stoll",    "stoull",       "stoi",
        "stod",    "stof",     "vector::", "_M_",          "terminate called",
        "what():", "yaml-cpp", "YAML::",   "bad_",         "Assertion",
        "(null)",  "Success",  "nullptr",  "out_of_range", "invalid_argument"}) {
    if (err.find(internal) != std::string::npos)
      failures.push_back(std::string("stderr shows an internal text '") + internal + "'");
  }
  const std::vector<std::string> lines = lines_of(err);
  std::size_t error_lines = 0, warning_lines = 0;
  std::size_t first_error = lines.size();
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].rfind("talus: error: ", 0) == 0) {
      ++error_lines;
      first_error = std::min(first_error, i);
    } else if (lines[i].find("warning: ") != std::string::npos) {
      ++warning_lines;
    }
    // An echoed input (a 100 kB argument, a whole file line) makes a line this long; the longest
    // true message (an unknown key with its list of the allowed ones) is under 400 characters.
    if (lines[i].size() > 600)
      failures.push_back("a stderr line of " + std::to_string(lines[i].size()) +
                         " characters (an input echoed whole?)");
  }
  if (error_lines != 1)
    failures.push_back("stderr has " + std::to_string(error_lines) +
                       " lines starting 'talus: error: ' (want exactly one)");
  if (warning_lines > c.warnings)
    failures.push_back(std::to_string(warning_lines) + " warning lines (want at most " +
                       std::to_string(c.warnings) + ")");
  // After the error only a usage line may follow (for an argument error).
  for (std::size_t i = first_error + 1; i < lines.size(); ++i)
    if (lines[i].rfind("usage: ", 0) != 0 && lines[i].rfind("  ", 0) != 0)
      failures.push_back("an unexpected line after the error: '" + lines[i] + "'");
  if (first_error < lines.size()) {
    const std::string& line = lines[first_error];
    // A location given twice ("FILE:3:4: FILE:3:4: ...") or a second "error:".
    static const std::regex doubled(R"(([^ :]+:[0-9]+(:[0-9]+)?: ).*\1)");
    if (std::regex_search(line, doubled)) failures.push_back("a location prefix twice");
    if (line.find("error:", 14) != std::string::npos) failures.push_back("'error:' twice");
    if (line.size() > 14 && line.find_first_not_of(" .:", 14) == std::string::npos)
      failures.push_back("an empty message");
  }
  if (r.exit_code != 0 && !r.out.empty())
    failures.push_back("stdout is not empty: '" + r.out.substr(0, 200) + "'");
  return failures;
}

// Every regular file under `root` (none if it does not exist) and its contents.
std::map<std::string, std::string> files_under(const fs::path& root) {
  std::map<std::string, std::string> files;
  if (!fs::is_directory(root)) return files;
  for (const auto& entry : fs::recursive_directory_iterator(root))
    if (entry.is_regular_file())
      files[entry.path().string()] = talus_test::read_file(entry.path().string());
  return files;
}

class BadInput : public testing::TestWithParam<Case> {};

TEST_P(BadInput, IsRefusedClearly) {
  const Case& c = GetParam();
  ASSERT_TRUE(c.problem.empty()) << c.group << "/" << c.name << ": " << c.problem;
#ifndef TALUS_HAVE_OPENCV
  if (c.needs_opencv) GTEST_SKIP() << "talus was built without OpenCV: no talus render to refuse";
#endif
  const std::string dir = talus_test::fresh_directory("test-bad-input", c.group + "-" + c.name);
  std::string scene;
  if (!c.scene.empty()) scene = talus_test::write_scene(dir, c.scene);
  for (const auto& [name, text] : c.files) {
    const fs::path path = fs::path(dir) / name;
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << text;
  }
  for (const auto& [action, value] : c.setup) {
    const std::string arg = substitute(value, dir, scene);
    // PATH:REST for the actions that take two parts (paths here hold no ':').
    const std::size_t colon = arg.find(':');
    const std::string path = arg.substr(0, colon);
    const std::string rest = colon == std::string::npos ? "" : arg.substr(colon + 1);
    if (action == "mkdir") {
      fs::create_directories(arg);
    } else if (action == "fifo") {
      ASSERT_EQ(mkfifo(arg.c_str(), 0600), 0) << arg;
    } else if (action == "remove") {
      fs::remove_all(arg);
    } else if (action == "talus") {  // a run before the case's own, which must succeed
      std::vector<std::string> words;
      std::istringstream in(arg);
      for (std::string w; in >> w;) words.push_back(w);
      const ProcessResult before = run_talus(words);
      ASSERT_EQ(before.exit_code, 0) << "setup run " << arg << ":\n" << before.err;
    } else if (action == "truncate") {  // PATH:BYTES
      fs::resize_file(path, std::stoull(rest));
    } else if (action == "corrupt") {  // PATH:OFFSET (negative: from the end); the byte inverted
      std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
      const long long size = static_cast<long long>(fs::file_size(path));
      const long long offset = std::stoll(rest) < 0 ? size + std::stoll(rest) : std::stoll(rest);
      ASSERT_TRUE(f && offset >= 0 && offset < size) << arg;
      f.seekg(offset);
      const char byte = static_cast<char>(~f.get());
      f.seekp(offset);
      f.put(byte);
    } else if (action == "append") {  // PATH:TEXT
      std::ofstream(path, std::ios::binary | std::ios::app) << rest;
    } else if (action == "write") {  // PATH:TEXT, replacing the file
      std::ofstream(path, std::ios::binary) << rest;
    } else if (action == "copy") {  // FROM:TO
      fs::copy(path, rest, fs::copy_options::overwrite_existing | fs::copy_options::recursive);
    } else {
      FAIL() << "unknown setup action '" << action << "'";
    }
  }
  const fs::path out = fs::path(dir) / "out";
  const std::map<std::string, std::string> before = files_under(out);
  std::vector<std::string> args;
  for (const std::string& a : c.args) args.push_back(substitute(a, dir, scene));
  const ProcessResult r = run_talus(args);

  EXPECT_EQ(r.exit_code, c.exit_code) << r.err;
  for (const std::string& fragment : c.fragments)
    EXPECT_NE(r.err.find(substitute(fragment, dir, scene)), std::string::npos)
        << "want '" << substitute(fragment, dir, scene) << "' in stderr:\n"
        << r.err;
  for (const std::string& failure : check_message(c, r)) ADD_FAILURE() << failure << ":\n" << r.err;
  // A refused run leaves no output behind and changes none that was there (from a setup run):
  // the lock file of a run refused after taking it is the only file it may add; it holds no data.
  if (r.exit_code != 0) {
    const std::map<std::string, std::string> after = files_under(out);
    for (const auto& [path, text] : after) {
      if (fs::path(path).filename() == ".talus.lock") continue;
      const auto was = before.find(path);
      if (was == before.end())
        ADD_FAILURE() << "a refused run left " << path;
      else if (was->second != text)
        ADD_FAILURE() << "a refused run changed " << path;
    }
    for (const auto& [path, text] : before)
      if (!after.count(path)) ADD_FAILURE() << "a refused run removed " << path;
  }
}

std::string case_name(const testing::TestParamInfo<Case>& info) {
  std::string name = info.param.group + "_" + info.param.name;
  for (char& ch : name)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(Table, BadInput, testing::ValuesIn(all_cases()), case_name);

// The table's own health: names unique (gtest would refuse duplicates at run time, this says
// which), and at least the size the issue asks for.
TEST(BadInputTable, NamesAreUniqueAndTheTableHasAtLeast300Cases) {
  std::set<std::string> names;
  for (const Case& c : all_cases())
    EXPECT_TRUE(names.insert(c.group + "/" + c.name).second) << "duplicate " << c.name;
  EXPECT_GE(all_cases().size(), 300u);
}

// Each base scene, unedited, runs and exits 0: so a case's error comes from its own edit.
TEST(BadInputTable, EveryBaseSceneRuns) {
  all_cases();
  for (const Base& base : g_bases) {
    const std::string dir =
        talus_test::fresh_directory("test-bad-input", "base-" + base.group + "-" + base.name);
    const std::string scene = talus_test::write_scene(dir, base.scene);
    const ProcessResult r = run_talus({"run", "--quiet", "--output", dir + "/out", scene});
    EXPECT_EQ(r.exit_code, 0) << base.group << "/" << base.name << ":\n" << r.err;
  }
}

}  // namespace
