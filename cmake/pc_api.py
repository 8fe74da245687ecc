#!/usr/bin/env python3
"""Marks the public API of polarcam with PC_API (polarcam/export.h).

    cmake/pc_api.py [--check] [HEADER...]

With no HEADER, every public header of the layers (*/include/polarcam/*.h and *.h.in) is done.
Each function declared at file scope (outside struct bodies, typedefs, macros and static inline
definitions) gets PC_API in front of its declaration, and the header includes
"polarcam/export.h". Idempotent: run it again after adding or changing declarations.
--check changes nothing and exits 1 when a header would change (a CI check).

The parse is deliberately small (comments, strings, preprocessor lines and brace depth); it
handles the declaration styles of this project's headers. The test `api_exports` checks the
result independently: libpolarcam.so must export exactly the functions declared in the
installed headers.
"""
import glob
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LAYERS = ("core", "io", "sim", "calib", "devices")
EXPORT_INCLUDE = '#include "polarcam/export.h"'
# headers that define PC_API or declare nothing
SKIP = {"export.h"}


def blank_out(text):
    """text with comments, string/char literals and preprocessor lines replaced by spaces
    (newlines kept), so that offsets stay valid."""
    out = list(text)
    i, n = 0, len(text)
    at_line_start = True
    while i < n:
        c = text[i]
        if at_line_start and c in " \t":
            i += 1
            continue
        if at_line_start and c == "#":
            # preprocessor line, with continuations
            j = i
            while j < n and text[j] != "\n":
                if text[j] == "\\" and j + 1 < n and text[j + 1] == "\n":
                    j += 2
                    continue
                # a comment inside the directive ends on its own
                if text.startswith("/*", j):
                    k = text.find("*/", j + 2)
                    k = n if k < 0 else k + 2
                    j = k
                    continue
                j += 1
            for k in range(i, j):
                if out[k] != "\n":
                    out[k] = " "
            i = j
            continue
        at_line_start = False
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            for k in range(i, j):
                if out[k] != "\n":
                    out[k] = " "
            i = j
            continue
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            for k in range(i, j):
                out[k] = " "
            i = j
            continue
        if c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            # keep extern "C" recognisable
            if text[i:j + 1] != '"C"':
                for k in range(i, min(j + 1, n)):
                    if out[k] != "\n":
                        out[k] = " "
            i = j + 1
            continue
        if c == "\n":
            at_line_start = True
        i += 1
    return "".join(out)


FUNC_NAME = re.compile(r"\b(pc_\w+)\s*\(")


def declarations(text):
    """(offset of the first character, statement text) of every file-scope function
    declaration that should carry PC_API."""
    clean = blank_out(text)
    result = []
    depth = 0          # braces, not counting extern "C" blocks
    extern_c = 0       # open extern "C" { blocks
    start = None       # offset where the current statement began
    i, n = 0, len(clean)
    while i < n:
        c = clean[i]
        if depth == 0 and start is None:
            if c.isspace() or c == ";":
                i += 1
                continue
            m = re.compile(r'extern\s*"C"\s*\{').match(clean, i)
            if m:
                extern_c += 1
                i = m.end()
                continue
            if c == "}" and extern_c:
                extern_c -= 1
                i += 1
                continue
            start = i
        if c == "{":
            depth += 1
        elif c == "}":
            depth -= 1
            if depth == 0:
                stmt = clean[start:i + 1]
                head = stmt[: stmt.find("{")]
                # a function definition (static inline) ends at its closing brace
                if re.search(r"\)\s*(__attribute__\s*\(\(.*\)\)\s*)?$", head.strip(), re.S):
                    start = None
        elif c == ";" and depth == 0:
            stmt = clean[start:i + 1]
            first = stmt.split()[0] if stmt.split() else ""
            if first not in ("typedef", "static", "struct", "enum", "union", "PC_API") \
                    and "{" not in stmt:
                m = FUNC_NAME.search(stmt)
                # a function, not a pointer to one: the name is followed by its parameters
                if m and not re.search(r"\(\s*\*\s*" + m.group(1), stmt):
                    result.append((start, stmt))
            start = None
        i += 1
    return result


def annotate(text):
    decls = declarations(text)
    out = text
    for start, _ in sorted(decls, reverse=True):
        out = out[:start] + "PC_API " + out[start:]
    if decls and EXPORT_INCLUDE not in out:
        out = add_include(out)
    return out, len(decls)


def add_include(text):
    """text with the export.h include in the first block of includes: among the
    "polarcam/..." ones in sorted order, else after the system ones, else after the guard."""
    lines = text.split("\n")
    own, system, guard = [], [], None
    for k, line in enumerate(lines):
        if line.startswith("#ifdef __cplusplus"):
            break
        if line.startswith('#include "polarcam/'):
            own.append(k)
        elif line.startswith("#include <"):
            system.append(k)
        elif guard is None and re.match(r"#define POLARCAM_\w+_H\b", line):
            guard = k
    if own:
        at = next((k for k in own if lines[k] > EXPORT_INCLUDE), own[-1] + 1)
        lines.insert(at, EXPORT_INCLUDE)
    elif system:
        lines[system[-1] + 1:system[-1] + 1] = ["", EXPORT_INCLUDE]
    elif guard is not None:
        lines[guard + 1:guard + 1] = ["", EXPORT_INCLUDE]
    else:
        raise SystemExit("cannot place the export.h include")
    return "\n".join(lines)


def public_headers():
    hs = []
    for layer in LAYERS:
        hs += glob.glob(os.path.join(ROOT, layer, "include", "polarcam", "*.h"))
        hs += glob.glob(os.path.join(ROOT, layer, "include", "polarcam", "*.h.in"))
    return sorted(hs)


def main(argv):
    check = "--check" in argv
    files = [a for a in argv if a != "--check"] or public_headers()
    changed = []
    for path in files:
        if os.path.basename(path) in SKIP:
            continue
        with open(path, encoding="utf-8") as f:
            text = f.read()
        new, count = annotate(text)
        if new != text:
            changed.append((path, count))
            if not check:
                with open(path, "w", encoding="utf-8") as f:
                    f.write(new)
    for path, count in changed:
        rel = os.path.relpath(path, ROOT)
        print(("would annotate " if check else "annotated ") + rel)
    return 1 if (check and changed) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
