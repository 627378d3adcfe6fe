#!/usr/bin/python3
"""Every repository path that the docs and comments name must exist.

Scans the tracked text files (`git ls-files`, else a walk without .git and build*/): Markdown
files whole, and the comments of C++/CUDA, Python, CMake and shell scripts. A token is taken for
a repository path when it is made of path characters and either ends in a known extension or
has a `/` after a first part that names a tracked folder (`step/`, `laws/`, `solver/`, ...), so
that prose like `m/s` or `V/A_ref` is left alone. It resolves when it exists relative to the
repository root, the referring file's folder, `solver/`, `reference/` or `tests/`; when a name
without extension names a module (`io/vtk_output`: its .hpp or .cpp); or when it is a suffix of
a tracked path at a `/` (`laws/volume_law.hpp`). Not repository paths: URLs, absolute paths,
placeholders (`<...>`, `{...}`, `*`, `$VAR`, `...`), what runs write (OUTPUT_ROOTS) and the
ALLOWED names below. Prints each dangling path as `file:line: path`; exit status 1 if any.

Usage: check_paths.py [REPO_ROOT] (default: two folders above this script).
"""

import os
import re
import subprocess
import sys

EXTENSIONS = ("hpp", "cpp", "cu", "cuh", "h", "md", "py", "yaml", "csv", "png", "json", "txt",
              "sh", "cmake", "obj", "stl", "in")
MODULE_EXTENSIONS = (".hpp", ".cpp", ".cu", ".cuh", ".py")
# First parts of the paths that builds and runs create (never tracked): build folders, the
# built-in scene's output, gpu-check's $OUT, scratch space, a run's frames and ParaView files,
# the beds' output roots of experiments/beds/README.md, `--output out`.
OUTPUT_ROOTS = re.compile(r"^(build[^/]*|talus-default|gpu-out|scratch|frames|vtk|beds-out|out)/")
# Names the docs use that are not repository paths, each with why: regular expressions matched
# against the whole token, or against "referring/file: token" for one file's use of it.
ALLOWED = {
    r"probes\.csv": "a run's probe file (the default of outputs.probes.file)",
    r"(trajectory|frame)_\d+\.(csv|png|h5)": "a frame that a run or talus render writes",
    r"(run|summary|render)\.json": "what a run, run_beds.sh or talus render writes",
    r"runs\.csv|cases\.txt": "experiments/beds: what run_beds.sh and make_scenes.py write",
    r"bed\.(json|md|png)": "experiments/fixed_bed: what fixed_bed.py writes into its output",
    r"filling\.json": "experiments/fixed_bed: the height curve fixed_bed.py digests per sitting",
    r"stiffness\.(json|md|png)": "experiments/fixed_bed: what stiffness_study.py writes",
    r"silo\.(json|md|png|obj)": "experiments/silo: what silo.py writes into its output",
    r"(study|case)\.(json|md|png)":
        "experiments/platonic_packing: what platonic_packing.py writes into its output",
    r"environment\.txt|profile\.txt|bench_\w+\.json|ncu_\w+\.(csv|txt)":
        "scripts/gpu-check: the files it writes into $OUT",
    r"ab\.txt": "scripts/gpu-ab: the summary it writes into $OUT",
    r"validation-(results\.json|summary\.md)|checks\.csv|figure\.(png|log)|fields\.csv"
    r"|detections\.csv":
        "what talus validate writes into its output directory (validation/README.md)",
    r"(drum|fill|errors)\.yaml": "the scene file named in examples of error messages",
    r"mpi\.h": "MPI's header (a system header of Open MPI, docs/parallel.md)",
    r"sysexits\.h": "the C library's header that names exit status 75 (EX_TEMPFAIL)",
    r"settle-sittings\.json": "what run_scaling.py writes beside a settle --settle-sitting stopped",
    r"scenes/grains/missing\.stl": "docs/scenes.md: the missing mesh of an error example",
    r"path\.(obj|stl)|SCENE\.yaml|NAME\.cu": "placeholders for a file the user names",
    r"README\.md: free_fall_drag/(frames|probes\.csv)": "the example run's outputs, as printed",
    r"docs/scenes\.md: \.\./meshes/plate\.obj": "relative to the scene file it shows, "
        "tests/scene/data/walls/mesh.yaml",
}
PATH_RUN = re.compile(r"[A-Za-z0-9_.\-/+$<>{}*?~…]+")
URL = re.compile(r"\b[a-z][a-z0-9+.\-]*://\S+|\bwww\.\S+")
PLACEHOLDER = re.compile(r"[<>{}*?$~…]|\.\.\.|(^|/)[A-Z][A-Z0-9_]*/")  # ..., DIR/
CODE_FILES = (".cpp", ".hpp", ".cu", ".cuh", ".h")
HASH_FILES = (".py", ".cmake", ".sh")


def tracked_files(root):
    try:
        out = subprocess.run(["git", "-C", root, "ls-files"], capture_output=True, text=True,
                             check=True).stdout
        return [f for f in out.splitlines() if os.path.isfile(os.path.join(root, f))]
    except (OSError, subprocess.CalledProcessError):
        found = []
        for folder, dirs, files in os.walk(root):
            dirs[:] = [d for d in dirs if d != ".git" and not d.startswith("build")]
            found += [os.path.relpath(os.path.join(folder, f), root) for f in files]
        return found


def c_comments(text):
    """(line, comment text) of // and /* */ comments, strings and raw strings skipped."""
    i, line, n, in_block = 0, 1, len(text), False
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
        if in_block:
            end = text.find("*/", i)
            end = n if end < 0 else end
            for k, part in enumerate(text[i:end].split("\n")):
                yield line + k, part
            line += text.count("\n", i, end)
            i, in_block = end + 2, False
            continue
        if text.startswith("//", i):
            end = text.find("\n", i)
            end = n if end < 0 else end
            yield line, text[i + 2:end]
            i = end
            continue
        if text.startswith("/*", i):
            i, in_block = i + 2, True
            continue
        if text.startswith('R"(', i):
            end = text.find(')"', i)
            end = n if end < 0 else end
            line += text.count("\n", i, end)
            i = end + 2
            continue
        if c == '"' or (c == "'" and re.match(r"'(\\.|[^\\'])'", text[i:i + 4])):
            end = i + 1
            while end < n and text[end] not in (c, "\n"):
                end += 2 if text[end] == "\\" else 1
            i = end + 1 if end < n and text[end] == c else end
            continue
        i += 1


def hash_comments(text):
    for number, row in enumerate(text.split("\n"), 1):
        match = re.search(r"(^|\s)#(?!!)(.*)$", row)
        if match:
            yield number, match.group(2)


def texts(path, text):
    """(line, text) pieces of a file that may name paths; none for other files."""
    name = os.path.basename(path)
    if path.endswith(".md"):
        return enumerate(text.split("\n"), 1)
    if path.endswith(CODE_FILES):
        return c_comments(text)
    is_script = path.startswith(("scripts/", ".ci/")) and "." not in name
    if path.endswith(HASH_FILES) or name == "CMakeLists.txt" or is_script:
        return hash_comments(text)
    return []


def candidates(piece, folders):
    for run in PATH_RUN.findall(URL.sub(" ", piece)):
        token = run.rstrip(".-+").lstrip("-+")
        while token.startswith("./"):
            token = token[2:]
        if not re.search(r"[A-Za-z]", token) or token.startswith("/"):
            continue
        if re.fullmatch(r"(\.[a-z]+/?)+", token):  # `.hpp/.cpp`: extensions, not a path
            continue
        has_extension = re.search(r"\.(%s)$" % "|".join(EXTENSIONS), token.rstrip("/"))
        if not has_extension and ("/" not in token or token.split("/")[0] not in folders):
            continue
        if not (PLACEHOLDER.search(token) or OUTPUT_ROOTS.match(token)):
            yield token


def allowed(token, referrer):
    return any(re.fullmatch(pattern, token) or re.fullmatch(pattern, referrer + ": " + token)
               for pattern in ALLOWED)


def resolves(token, referrer, root, suffixes):
    parts = token.rstrip("/").split("/")
    alternatives = []  # `overlap_batch.hpp/.cu`: the same name with another extension
    while len(parts) > 1 and re.fullmatch(r"\.[a-z]+", parts[-1]):
        alternatives.append(parts.pop())
    path = "/".join(parts)
    names = [path] + [os.path.splitext(path)[0] + a for a in alternatives]
    if "." not in parts[-1]:
        names += [path + e for e in MODULE_EXTENSIONS]
    bases = [root, os.path.join(root, os.path.dirname(referrer))]
    bases += [os.path.join(root, d) for d in ("solver", "reference", "tests")]
    for name in names:
        if any(os.path.exists(os.path.join(b, name)) for b in bases):
            return True
        if "/" + name in suffixes:
            return True
    return False


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", ".."))
    files = tracked_files(root)
    folders, suffixes = set(), set()
    for f in files:  # every tracked file and folder, and each of their tails after a `/`
        parts = f.split("/")
        folders.update(parts[:-1])
        for end in range(1, len(parts) + 1):
            suffixes.update("/" + "/".join(parts[k:end]) for k in range(end))
    dangling = 0
    for path in sorted(files):
        try:
            with open(os.path.join(root, path), encoding="utf-8") as f:
                text = f.read()
        except (UnicodeDecodeError, OSError):
            continue
        for number, piece in texts(path, text):
            for token in candidates(piece, folders):
                if not (allowed(token, path) or resolves(token, path, root, suffixes)):
                    print("%s:%d: %s" % (path, number, token))
                    dangling += 1
    if dangling:
        print("%d dangling path(s): fix the reference, or list a name that is not a repository "
              "path in ALLOWED (tests/docs/check_paths.py) with its reason" % dangling)
        return 1
    print("docs_paths: every path named in %d files exists" % len(files))
    return 0


if __name__ == "__main__":
    sys.exit(main())
