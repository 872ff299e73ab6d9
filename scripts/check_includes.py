#!/usr/bin/env python3
"""The architecture's rules as a check: which folder may include which, where SQL lives, sizes, citations.

Usage: scripts/check_includes.py [--root ROOT]   check the tree at ROOT (default: this repository)
       scripts/check_includes.py --self-test     check tests/fixtures/check_includes/tree and compare
                                                 the report with tests/fixtures/check_includes/expected.txt

Prints one line per violation, `path:line: [rule] message`, sorted, and exits 1 if there is any
(0 if none, 2 on a usage error). Python 3 standard library only. docs/ARCHITECTURE.md says the
same rules in prose; change both together.

Rules
  layer          every `#include "…"` and `#include <…>` of a C++ file under SOURCE_FOLDERS is
                 resolved as the compiler would (the including file's folder first for quoted
                 names, then each library's public include folder, INCLUDE_ROOTS, as the
                 CMakeLists.txt files declare them) to a file of ours, whose layer (LAYERS) must be
                 the includer's own or one it may use (ALLOWED).
  store-internal outside server/store/, only the server's wiring and the leaves (tests, bench,
                 fuzz) include a store header other than its interface (STORE_INTERFACE).
  external       a header that is not ours (standard library, third-party, system) must be one
                 the layer may use (EXTERNAL_RULES): the pure core and client-lib's motion code
                 use no I/O, thread or JSON header; JSON in the server only in http/ and main.cpp.
  pure           no `thread_local` in the pure layers (PURE_LAYERS): per-thread state is the
                 caller's (a workspace passed in), so the core stays testable and reentrant.
  unresolved     a quoted include that names no file of ours (nothing to check it against).
  sql            SQL statement text (SELECT …, INSERT INTO, UPDATE … SET, DELETE FROM, CREATE
                 TABLE/INDEX, …, upper case) in a string literal outside SQL_HOMES.
  file-length    a .cpp/.hpp under SIZE_FOLDERS over FILE_LIMIT lines.
  function-length a function under SIZE_FOLDERS over FUNCTION_LIMIT lines. Heuristic: comments,
                 strings and preprocessor lines are blanked, then a brace block at namespace or
                 class level whose header has a parenthesis (and is not a class, namespace or an
                 `=` initializer) is a function; it runs from the header's first line to its closing
                 brace, a constructor's braced member initializers included. A lambda counts in
                 the function that holds it.
  citation       a comment citing a tracker item or a task ("issue 17", "seed 004") in a C++,
                 CMake, shell, Python, JavaScript or SQL file of ours (SOURCE_FOLDERS and
                 CITATION_FOLDERS): comments say why, citing docs/spec.md or papers. Comments are
                 found by the C++ lexer below (C++ and JavaScript), `--` (SQL) or `#` after a blank
                 or at a line's start (the rest), so a `#` inside a shell string may count.
  exception      an entry of an exception table that no longer matches anything (remove it: the
                 tables only shrink).

Today's code breaks some rules; each such place is an entry of an exception table below with a
one-line reason, and for the size and citation rules a ceiling (the size or count of today), so it
may shrink but not grow, and no new place may join it without an entry here.
"""

import argparse
import os
import re
import sys
from dataclasses import dataclass, field

SOURCE_FOLDERS = ["shared", "client-lib", "server", "datasets", "sim", "tools", "geojson", "imaging",
                  "tests", "bench", "fuzz"]
SKIPPED = ["tests/fixtures"]  # data, and this check's own fixture tree (which breaks every rule)
CPP_SUFFIXES = (".cpp", ".hpp", ".h", ".cc")

# Where a name that is not beside its includer is looked for: each library's public include
# folder (target_include_directories in the folder's CMakeLists.txt).
INCLUDE_ROOTS = ["shared/include", "client-lib/motion/include", "client-lib/api/include", "geojson/include", "imaging/include",
                 "datasets/include", "sim/include", "server", "tools", "tests/support"]

# Layers: the first prefix a file's path starts with names its layer.
LAYERS = [
    ("shared/", "shared"),
    ("geojson/", "geojson"),
    ("imaging/", "imaging"),
    ("client-lib/motion/include/locus/motion/pdr/", "client-lib/pdr"), ("client-lib/motion/src/pdr/", "client-lib/pdr"),
    ("client-lib/motion/include/locus/motion/fusion/", "client-lib/fusion"), ("client-lib/motion/src/fusion/", "client-lib/fusion"),
    ("client-lib/motion/include/locus/motion/relative/", "client-lib/relative"),
    ("client-lib/motion/src/relative/", "client-lib/relative"),
    ("client-lib/api/include/locus/api/", "client-lib/api"), ("client-lib/api/src/", "client-lib/api"),
    ("server/store/", "server/store"),
    ("server/localize/", "server/localize"),
    ("server/routing/", "server/routing"),
    ("server/directory/", "server/directory"),
    ("server/transmitters/", "server/transmitters"),
    ("server/tuning/", "server/tuning"),
    ("server/tracks/", "server/tracks"),
    ("server/floors/", "server/floors"),
    ("server/http/", "server/http"),
    ("server/startup/", "server/startup"),
    ("server/main.cpp", "server/main"),
    ("datasets/", "datasets"),
    ("sim/", "sim"),
    ("tools/commands/", "tools/commands"),
    ("tools/", "tools"),
    # Where the build put the binaries and where the data sets are: the tests' and benchmarks'.
    ("tests/support/build_paths.", "build-paths"),
    ("tests/", "tests"),
    ("bench/", "bench"),
    ("fuzz/", "fuzz"),
]

MOTION = ["client-lib/pdr", "client-lib/fusion", "client-lib/relative"]
CLIENT = MOTION + ["client-lib/api"]
SERVER_SERVICES = ["server/store", "server/localize", "server/routing", "server/directory", "server/transmitters",
                   "server/tuning", "server/tracks", "server/floors"]
SERVER = SERVER_SERVICES + ["server/http", "server/startup"]
LIBRARIES = ["shared", "geojson", "imaging"] + CLIENT + ["datasets", "sim"]

# Which layers a layer may include besides its own. Arrows point down: the core includes nothing,
# the device's code no server, the server no CLI, and nothing but tests includes tests/.
ALLOWED = {
    "shared": [],
    "geojson": ["shared"],
    "imaging": ["shared"],
    "client-lib/pdr": ["shared"],
    "client-lib/fusion": ["shared", "client-lib/pdr"],
    "client-lib/relative": ["shared", "client-lib/pdr"],
    "client-lib/api": ["shared", "geojson"],
    "server/store": ["shared"],
    "server/localize": ["shared", "server/store"],
    "server/routing": ["shared", "server/store"],
    "server/directory": ["shared", "server/store"],
    "server/transmitters": ["shared", "server/store"],
    "server/tuning": ["shared", "server/store"],
    # Thin clients' fusion runs client-lib's filters on the server (tracks/fusion.hpp); their
    # scans are localized by the localize service's matcher or ranged on the transmitters, and
    # their GNSS placed by the floors' georeferences (tracks/map_scans.hpp).
    "server/tracks": ["shared", "server/store", "client-lib/pdr", "client-lib/fusion", "server/localize", "server/transmitters",
                      "server/floors"],
    "server/floors": ["shared", "server/store"],
    "server/http": ["shared", "geojson"] + SERVER_SERVICES,
    "server/startup": ["shared", "server/store"],
    "server/main": ["shared", "geojson"] + SERVER,
    "datasets": ["shared", "client-lib/pdr"],
    "sim": ["shared"] + MOTION,
    "tools": LIBRARIES,
    "tools/commands": LIBRARIES + ["tools"],
    "tests": LIBRARIES + SERVER + ["server/main", "tools", "tools/commands", "build-paths"],
    "bench": LIBRARIES + SERVER + ["tools", "build-paths"],
    "build-paths": [],
    "fuzz": LIBRARIES + SERVER + ["tools"],
}

# The store's interface: the typed documents, the Store and its change feed, the resource kinds,
# Db (for its error type), the live tracks' repository (their SQL, on their own connection), and
# the per-floor cache on the change feed. Its other headers are the backends.
STORE_INTERFACE = ["server/store/store.hpp", "server/store/documents.hpp", "server/store/kinds.hpp",
                   "server/store/db.hpp", "server/store/track_repository.hpp", "server/store/floor_cache.hpp"]
STORE_INTERNAL_USERS = ["server/store", "server/main", "tests", "bench", "fuzz"]

# Headers that are not ours, by group. A name with neither a dot nor a slash is the standard library.
EXTERNAL_GROUPS = [
    (r"nlohmann/", "json"), (r"httplib\.h$", "httplib"), (r"sqlite3\.h$", "sqlite"), (r"libpq-fe\.h$", "libpq"),
    (r"openssl/", "openssl"), (r"Eigen/", "eigen"), (r"opencv2/", "opencv"), (r"utf8proc\.h$", "utf8proc"),
    (r"(png|jpeglib|jerror)\.h$", "image-codecs"), (r"zlib\.h$", "zlib"), (r"CLI/", "cli11"),
    (r"(gtest|gmock)/", "gtest"), (r"benchmark/", "benchmark"),
]
IO_STD = {"fstream", "iostream", "istream", "ostream", "iosfwd", "sstream", "cstdio", "filesystem", "thread",
          "mutex", "shared_mutex", "condition_variable", "future", "atomic", "stop_token", "semaphore"}


@dataclass
class ExternalRule:
    """Which header groups a layer may use: `allowed` (None: any but `denied`), and groups
    confined to some of its paths (`only_in`). `std-io` is the standard library's IO_STD."""
    where: str
    allowed: set = None
    denied: set = field(default_factory=set)
    only_in: dict = field(default_factory=dict)  # group -> path prefixes it is confined to
    reason: str = ""

    def permits(self, group, path):
        if group in self.denied or (self.allowed is not None and group not in self.allowed):
            return False
        confined = self.only_in.get(group)
        return confined is None or any(path.startswith(p) for p in confined)


PURE = {"std"}
MOTION_PURE = "motion code runs on the phone: pure (no I/O, threads, JSON or networking)"
TYPED = "services take and return typed documents: JSON is http/'s, HTTP is http/'s"
EXTERNAL_RULES = [
    ExternalRule("shared", PURE | {"eigen", "utf8proc"},
                 only_in={"eigen": ["shared/src/ranging/"], "utf8proc": ["shared/src/directory/text.cpp"]},
                 reason="pure core: no I/O, threads or JSON; Eigen private to ranging's .cpp files, "
                        "utf8proc to name folding"),
    ExternalRule("client-lib/pdr", PURE | {"eigen"}, reason=MOTION_PURE),
    ExternalRule("client-lib/fusion", PURE | {"eigen"}, reason=MOTION_PURE),
    ExternalRule("client-lib/relative", PURE | {"eigen"}, reason=MOTION_PURE),
    ExternalRule("geojson", PURE | {"json"}, reason="the GeoJSON codec: JSON text in and out, no I/O"),
    ExternalRule("imaging", PURE | {"opencv"}, only_in={"opencv": ["imaging/src/"]},
                 reason="vectorising a drawing: no file I/O (the CLI reads it), OpenCV private to the .cpp"),
    ExternalRule("server/store", denied={"json", "httplib"}, reason=TYPED),
    ExternalRule("server/localize", denied={"json", "httplib"}, reason=TYPED),
    ExternalRule("server/routing", denied={"json", "httplib"}, reason=TYPED),
    ExternalRule("server/directory", denied={"json", "httplib"}, reason=TYPED),
    ExternalRule("server/transmitters", denied={"json", "httplib"}, reason=TYPED),
    ExternalRule("server/tuning", denied={"json", "httplib"}, reason=TYPED),
    ExternalRule("server/tracks", denied={"json", "httplib"}, reason=TYPED),
    ExternalRule("server/floors", denied={"json", "httplib"}, reason=TYPED),
    ExternalRule("server/startup", denied={"json", "httplib"}, reason=TYPED),
]

PURE_LAYERS = ["shared"] + ["client-lib/pdr", "client-lib/fusion", "client-lib/relative"]

# Where SQL text may live (schema/ holds .sql files only, so it needs no scanning).
SQL_HOMES = ["server/store/", "schema/",
             # Tests make database states no API call can make (a damaged row, an old schema) and
             # check the store's SQL dialect translation against real statements.
             "tests/"]
SQL_PATTERNS = [r"\bSELECT\s+\S", r"\bINSERT\s+(OR\s+[A-Z]+\s+)?INTO\b", r"\bUPDATE\s+\w+\s+SET\b",
                r"\bDELETE\s+FROM\b", r"\bCREATE\s+(TABLE|INDEX|UNIQUE\s+INDEX|TRIGGER|VIEW)\b",
                r"\bDROP\s+(TABLE|INDEX)\b", r"\bALTER\s+TABLE\b"]

SIZE_FOLDERS = ["server/", "shared/", "client-lib/"]
FILE_LIMIT = 500
FUNCTION_LIMIT = 120

CITATION = re.compile(r"\bissues?\s*#?\d+|\bseed\s+0\d+", re.IGNORECASE)
CITATION_FILES = CPP_SUFFIXES + (".sh", ".py", "CMakeLists.txt", ".cmake", ".js", ".mjs", ".sql")
CITATION_FOLDERS = ["scripts", "schema", "web"]  # checked for citations only, besides SOURCE_FOLDERS

# ---------------------------------------------------------------------------------------------
# Exceptions: today's code where it breaks a rule. Each goes when its reason does.

# (including file, included file) -> reason; for the layer and store-internal rules.
INCLUDE_EXCEPTIONS = {
    ("tools/commands/migrate.cpp", "server/store/copy.hpp"):
        "`locus migrate` copies a database through the store; the CLI links the server library for it",
    ("tools/commands/migrate.cpp", "server/store/migrations.hpp"):
        "`locus migrate` brings both databases to the binary's schema with the server's migrations",
    ("bench/plan_store_bench.cpp", "tests/support/images/test_images.hpp"):
        "the plan-store bench makes plan images with the tests' image writer",
}

# (file, header group) -> reason; for the external rule.
EXTERNAL_EXCEPTIONS = {
    ("server/store/pg_changes.cpp", "json"):
        "PostgreSQL's NOTIFY payload between servers is a small JSON object, not an API document",
    ("server/tracks/fusion_options.hpp", "json"):
        "a track's fusion options are written as JSON by tracks/ (json_fwd.hpp); the writer belongs in http/",
    ("server/tracks/fusion_options.cpp", "json"):
        "the writer of the fusion options' JSON (fusion_options.hpp), until it moves to http/",
}

# file -> reason; SQL text outside the store. None today: the live tracks' SQL is the store's
# too (store/track_repository.cpp).
SQL_EXCEPTIONS = {}

# file -> lines it may not exceed (today's size). None today.
FILE_LENGTH_EXCEPTIONS = {}

# "file:function" -> lines it may not exceed (today's size). None today.
FUNCTION_LENGTH_EXCEPTIONS = {}

# file -> comments citing an issue or a seed it may not exceed. None today: comments cite the
# paper (docs/spec.md names them) or the section of docs/ that explains the behaviour.
CITATION_EXCEPTIONS = {}


@dataclass
class Config:
    """What one run checks against: the tables above, or the self-test's own."""
    include_exceptions: dict
    external_exceptions: dict
    sql_exceptions: dict
    file_length_exceptions: dict
    function_length_exceptions: dict
    citation_exceptions: dict
    file_limit: int = FILE_LIMIT
    function_limit: int = FUNCTION_LIMIT


def repository_config():
    return Config(INCLUDE_EXCEPTIONS, EXTERNAL_EXCEPTIONS, SQL_EXCEPTIONS, FILE_LENGTH_EXCEPTIONS,
                  FUNCTION_LENGTH_EXCEPTIONS, CITATION_EXCEPTIONS)


# ---------------------------------------------------------------------------------------------
# Reading C++: one pass splits a file into code (comments, literals and preprocessor lines
# blanked, newlines kept, so offsets and line numbers stay), string literals and comments.

@dataclass
class Lexed:
    code: str
    strings: list   # (line, text)
    comments: list  # (line, text)


def lex(text):
    out = list(text)
    strings, comments = [], []
    i, n, line = 0, len(text), 1
    at_line_start = True

    def blank(a, b):
        for k in range(a, b):
            if out[k] != "\n":
                out[k] = " "

    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
            at_line_start = True
            i += 1
            continue
        if c in " \t\r":
            i += 1
            continue
        if at_line_start and c == "#":
            # A preprocessor directive, continued by backslashes; comments in it still count.
            j = i
            while j < n and text[j] != "\n":
                if text.startswith("//", j):
                    break
                if text[j] == "\\" and j + 1 < n and text[j + 1] == "\n":
                    j += 2
                    line += 1
                    continue
                j += 1
            blank(i, j)
            i = j
            continue
        at_line_start = False
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            comments.append((line, text[i:j]))
            blank(i, j)
            i = j
            continue
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            comments.append((line, text[i:j]))
            blank(i, j)
            line += text.count("\n", i, j)
            i = j
            continue
        m = re.match(r'(?:u8|u|U|L)?R"([^()\\\s]{0,16})\(', text[i:i + 24])
        if m and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            close = text.find(")" + m.group(1) + '"', i + m.end())
            close = n if close < 0 else close
            end = min(n, close + len(m.group(1)) + 2)
            strings.append((line, text[i + m.end():close]))
            blank(i, end)
            line += text.count("\n", i, end)
            i = end
            continue
        if c == '"' or (c == "'" and not digit_separator(text, i)):
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            if c == '"':
                strings.append((line, text[i + 1:j - 1]))
            blank(i, j)
            i = j
            continue
        i += 1
    return Lexed("".join(out), strings, comments)


def digit_separator(text, i):
    """Whether the quote at i is inside a number (1'000'000) rather than opening a character."""
    j = i
    while j > 0 and (text[j - 1].isalnum() or text[j - 1] in "_'."):
        j -= 1
    return j < i and text[j].isdigit()


def line_of(text, pos):
    return text.count("\n", 0, pos) + 1


# ---------------------------------------------------------------------------------------------
# Functions: brace blocks at namespace or class level.

SCOPE_KEYWORD = re.compile(r"\b(class|struct|union|enum)\b|^extern$")
ATTRIBUTES = re.compile(r"\balignas\s*\([^()]*\)|\[\[[^\]]*\]\]|__attribute__\s*\(\([^()]*\)\)")
ACCESS = re.compile(r"^\s*((public|private|protected)\s*:\s*)+")


def matching_brace(code, i):
    depth = 0
    for j in range(i, len(code)):
        if code[j] == "{":
            depth += 1
        elif code[j] == "}":
            depth -= 1
            if depth == 0:
                return j
    return len(code) - 1


def paren_depth_and_top(s):
    """The parentheses still open at the end of s, and s without what is inside parentheses."""
    depth, kept = 0, []
    for ch in s:
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
        elif depth == 0:
            kept.append(ch)
    return depth, "".join(kept)


def next_char(code, k):
    while k < len(code) and code[k].isspace():
        k += 1
    return k


def functions(code):
    """Yields (name, first line, last line) of each function in blanked code."""
    start = 0  # where the current block's header begins (after the last ; { or } at this level)
    i, n = 0, len(code)
    while i < n:
        c = code[i]
        if c in ";}":
            start = i + 1
        elif c == "{":
            header = ATTRIBUTES.sub(" ", code[start:i])
            depth, top = paren_depth_and_top(header)
            top = top.strip()
            if depth > 0:  # a brace inside a parameter list (`Options o = {}`): still the header
                i = matching_brace(code, i)
            elif re.search(r"\bnamespace\b", top) or ("(" not in header and SCOPE_KEYWORD.search(top)):
                start = i + 1  # a namespace or class: its contents are at this level too
            elif "(" in header and ("operator" in top or "=" not in top):
                end = matching_brace(code, i)
                while True:  # a constructor's braced member initializers: `: a_{x}, b_{y} {`
                    k = next_char(code, end + 1)
                    if k < n and code[k] == ",":
                        k = code.find("{", k)
                        if k < 0:
                            break
                    elif not (k < n and code[k] == "{"):
                        break
                    end = matching_brace(code, k)
                body = code[start:i]
                lead = ACCESS.match(body)
                first = start + (lead.end() if lead else 0)
                first = next_char(code, first)
                yield function_name(header), line_of(code, first), line_of(code, end)
                i = end
                start = end + 1
            else:  # an initializer or anything else: skipped whole
                i = matching_brace(code, i)
                start = i + 1
        i += 1


def function_name(header):
    m = re.search(r"(operator\s*[^\s(]+|[~\w:]+)\s*\(", header)
    return m.group(1).split("::")[-1] if m else "?"


# ---------------------------------------------------------------------------------------------
# The checks.

def layer_of(path):
    for prefix, name in LAYERS:
        if path == prefix or path.startswith(prefix):
            return name
    return None


def external_group(name):
    for pattern, group in EXTERNAL_GROUPS:
        if re.search(pattern, name):
            return group
    if "." not in name and "/" not in name:
        return "std-io" if name in IO_STD else "std"
    return "system"


OUR_ANGLE_PREFIXES = ("locus/", "datasets/", "sim/")
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')


class Checker:
    def __init__(self, root, config):
        self.root = root
        self.config = config
        self.violations = []  # (path, line, rule, message)
        self.used = set()     # exception keys that matched

    def report(self, path, line, rule, message):
        self.violations.append((path, line, rule, message))

    def files(self, folders):
        for folder in folders:
            top = os.path.join(self.root, folder)
            for dirpath, dirnames, filenames in os.walk(top):
                rel_dir = os.path.relpath(dirpath, self.root).replace(os.sep, "/")
                dirnames[:] = sorted(d for d in dirnames if f"{rel_dir}/{d}" not in SKIPPED)
                for name in sorted(filenames):
                    yield f"{rel_dir}/{name}"

    def exists(self, rel):
        return os.path.isfile(os.path.join(self.root, rel))

    def resolve(self, path, quote, name):
        candidates = []
        if quote == '"':
            candidates.append(os.path.normpath(os.path.join(os.path.dirname(path), name)).replace(os.sep, "/"))
        candidates += [f"{r}/{name}" for r in INCLUDE_ROOTS]
        for c in candidates:
            if self.exists(c):
                return c
        return None

    def run(self):
        for path in self.files(SOURCE_FOLDERS):
            if path.endswith(CPP_SUFFIXES):
                text = self.read(path)
                lexed = lex(text)
                self.check_includes(path, text)
                self.check_pure(path, lexed)
                self.check_sql(path, lexed)
                self.check_sizes(path, text, lexed)
                self.check_citations(path, lexed.comments)
            elif path.endswith(CITATION_FILES):
                self.check_citations(path, comments_of(path, self.read(path)))
        for path in self.files(CITATION_FOLDERS):
            if path.endswith(CITATION_FILES):
                self.check_citations(path, comments_of(path, self.read(path)))
        self.check_stale()
        return sorted(self.violations, key=lambda v: (v[0], v[1], v[2], v[3]))

    def read(self, path):
        with open(os.path.join(self.root, path), encoding="utf-8", errors="replace") as f:
            return f.read()

    def check_includes(self, path, text):
        src = layer_of(path)
        if src is None:
            self.report(path, 1, "layer", "the file is in no layer (add its folder to LAYERS and ALLOWED)")
            return
        for number, line in enumerate(text.splitlines(), 1):
            m = INCLUDE.match(line)
            if not m:
                continue
            quote, name = m.groups()
            target = self.resolve(path, quote, name)
            if target is None:
                if quote == '"' or name.startswith(OUR_ANGLE_PREFIXES):
                    self.report(path, number, "unresolved", f'"{name}" is no file of ours')
                else:
                    self.check_external(path, number, src, name)
                continue
            dst = layer_of(target)
            key = (path, target)
            if dst != src and dst not in ALLOWED.get(src, []):
                if key in self.config.include_exceptions:
                    self.used.add(("include", key))
                else:
                    self.report(path, number, "layer", f"{src} may not include {dst} ({target})")
            elif (target.startswith("server/store/") and target not in STORE_INTERFACE
                  and src not in STORE_INTERNAL_USERS):
                if key in self.config.include_exceptions:
                    self.used.add(("include", key))
                else:
                    self.report(path, number, "store-internal",
                                f"{src} may include only the store's interface, not {target}")

    def check_external(self, path, number, src, name):
        group = external_group(name)
        for rule in EXTERNAL_RULES:
            if src != rule.where or rule.permits(group, path):
                continue
            key = (path, group)
            if key in self.config.external_exceptions:
                self.used.add(("external", key))
                continue
            self.report(path, number, "external", f"{src} may not include <{name}> ({group}: {rule.reason})")

    def check_pure(self, path, lexed):
        if layer_of(path) not in PURE_LAYERS:
            return
        for m in re.finditer(r"\bthread_local\b", lexed.code):
            self.report(path, line_of(lexed.code, m.start()), "pure",
                        "thread_local in a pure layer: pass per-thread state in (a workspace)")

    def check_sql(self, path, lexed):
        if any(path.startswith(h) for h in SQL_HOMES):
            return
        for line, text in lexed.strings:
            hit = next((p for p in SQL_PATTERNS if re.search(p, text)), None)
            if hit is None:
                continue
            if path in self.config.sql_exceptions:
                self.used.add(("sql", path))
                return
            snippet = " ".join(text.split())[:40]
            self.report(path, line, "sql", f'SQL outside server/store/: "{snippet}"')

    def check_sizes(self, path, text, lexed):
        if not any(path.startswith(f) for f in SIZE_FOLDERS):
            return
        lines = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
        self.ceiling(path, 1, "file-length", lines, self.config.file_limit,
                     self.config.file_length_exceptions, path, f"{path} has {lines} lines")
        for name, first, last in functions(lexed.code):
            size = last - first + 1
            key = f"{path}:{name}"
            self.ceiling(path, first, "function-length", size, self.config.function_limit,
                         self.config.function_length_exceptions, key, f"{name} has {size} lines")

    def ceiling(self, path, line, rule, value, limit, table, key, what):
        if value <= limit:
            return
        if key in table:
            self.used.add((rule, key))
            if value <= table[key]:
                return
            self.report(path, line, rule, f"{what}, over its ceiling of {table[key]} (limit {limit})")
        else:
            self.report(path, line, rule, f"{what}, over the limit of {limit}")

    def check_citations(self, path, comments):
        hits = [line for line, text in comments if CITATION.search(text)]
        if not hits:
            return
        table = self.config.citation_exceptions
        if path in table:
            self.used.add(("citation", path))
            if len(hits) <= table[path]:
                return
            self.report(path, hits[-1], "citation",
                        f"{len(hits)} comments cite an issue or a seed, over its ceiling of {table[path]}")
            return
        for line in hits:
            self.report(path, line, "citation", "comment cites an issue or a seed; cite docs/spec.md or a paper")

    def check_stale(self):
        tables = [("include", self.config.include_exceptions), ("external", self.config.external_exceptions),
                  ("sql", self.config.sql_exceptions), ("file-length", self.config.file_length_exceptions),
                  ("function-length", self.config.function_length_exceptions),
                  ("citation", self.config.citation_exceptions)]
        for rule, table in tables:
            for key in table:
                if (rule, key) not in self.used:
                    shown = " -> ".join(key) if isinstance(key, tuple) else key
                    path = key[0] if isinstance(key, tuple) else key.split(":")[0]
                    self.report(path, 0, "exception", f"{rule} exception no longer needed: {shown}")


def comments_of(path, text):
    """The comments of a file that is not C++: JavaScript's as C++'s, SQL's `--`, and `#` comments
    of shell, Python and CMake (a whole line, or after code)."""
    if path.endswith((".js", ".mjs")):
        return lex(text).comments
    marker = r"--" if path.endswith(".sql") else r"#(?![!{(])"
    out = []
    for number, line in enumerate(text.splitlines(), 1):
        m = re.search(r"(^|\s)" + marker + r"(.*)", line)
        if m:
            out.append((number, m.group(2)))
    return out


def format_violation(v):
    path, line, rule, message = v
    return f"{path}:{line}: [{rule}] {message}"


# ---------------------------------------------------------------------------------------------
# The self-test: a fixture tree with one violation of each rule, expected lines written by hand.

def self_test_config():
    return Config(
        include_exceptions={("tools/commands/excused.cpp", "server/store/store.hpp"): "fixture: an excused edge",
                            ("tools/commands/gone.cpp", "server/store/store.hpp"): "fixture: a stale entry"},
        external_exceptions={},
        sql_exceptions={"server/tracks/excused_sql.cpp": "fixture: excused SQL"},
        file_length_exceptions={"server/http/big.cpp": 30},
        function_length_exceptions={"shared/src/long.cpp:excused": 9},
        citation_exceptions={"sim/src/cited.cpp": 1},
        file_limit=20, function_limit=6)


def self_test(repo):
    base = os.path.join(repo, "tests", "fixtures", "check_includes")
    got = [format_violation(v) for v in Checker(os.path.join(base, "tree"), self_test_config()).run()]
    with open(os.path.join(base, "expected.txt"), encoding="utf-8") as f:
        want = [l for l in f.read().splitlines() if l and not l.startswith("#")]
    if got == want:
        print(f"self-test: the fixture tree gives the {len(want)} expected violations")
        return 0
    print("self-test FAILED")
    for line in want:
        if line not in got:
            print(f"  missing:    {line}")
    for line in got:
        if line not in want:
            print(f"  unexpected: {line}")
    return 1


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", help="the tree to check (default: this repository)")
    parser.add_argument("--self-test", action="store_true", help="check the fixture tree against its expected report")
    args = parser.parse_args()
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    if args.self_test:
        return self_test(repo)
    violations = Checker(args.root or repo, repository_config()).run()
    for v in violations:
        print(format_violation(v))
    if violations:
        print(f"{len(violations)} violations (docs/ARCHITECTURE.md, scripts/check_includes.py)", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
