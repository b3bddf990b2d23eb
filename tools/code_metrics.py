#!/usr/bin/env python3
"""Rough size and coupling numbers of csim's sources, to compare a branch before and after a cleanup.

Prints: files and lines per top folder; the largest class (lines of its definition, by brace matching
in headers and sources); the largest function (lines of its body, by brace matching in .cpp files);
the include arrows between folders (tools/include_graph.py); and the number of `dynamic_cast`s and of
`static_cast<`s to body types. The measures are textual and approximate, but the same script run on
two trees measures both the same way.

    python3 tools/code_metrics.py [repository root]
"""
import pathlib
import re
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import include_graph  # noqa: E402

TOP_FOLDERS = ["engine", "contact", "fem", "tools", "tests", "bench"]
SOURCE_SUFFIXES = {".h", ".hpp", ".cpp", ".cc", ".py", ".cmake", ".txt"}
BODY_TYPES = ["Body", "PointMass", "RigidBody2d", "RigidBody3d", "FeBody", "FixedBody"]
CLASS_HEAD = re.compile(r"^\s*(?:template\s*<[^>]*>\s*)?(class|struct)\s+(\w+)[^;{]*\{", re.MULTILINE)
# A function definition: a name with a parameter list, maybe qualifiers, then the opening brace.
FUNCTION_HEAD = re.compile(
    r"^[\w:<>,~*& \t]*?([\w:~]+(?:operator\S*)?)\s*\(([^;{}]*)\)\s*(?:const\s*)?(?:noexcept\s*)?(?:override\s*)?"
    r"(?:->\s*[\w:<>,*& ]+)?\s*(?::[^;{]*)?\{", re.MULTILINE)
NOT_FUNCTIONS = {"if", "for", "while", "switch", "catch", "return", "sizeof"}


def strip_comments_and_strings(text):
    """Blank out comments and string/char literals, keeping line breaks, so braces count right."""
    pattern = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', re.DOTALL)
    return pattern.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)


def matching_brace(text, open_index):
    depth = 0
    for i in range(open_index, len(text)):
        if text[i] == "{":
            depth += 1
        elif text[i] == "}":
            depth -= 1
            if depth == 0:
                return i
    return len(text) - 1


def lines_between(text, start, end):
    return text.count("\n", start, end) + 1


def largest(pattern, files, root, skip=()):
    best = (0, "", "")
    for path in files:
        text = strip_comments_and_strings(path.read_text(errors="replace"))
        for match in pattern.finditer(text):
            name = match.group(2) if pattern is CLASS_HEAD else match.group(1)
            if name in skip:
                continue
            open_index = match.end() - 1
            lines = lines_between(text, match.start(), matching_brace(text, open_index))
            if lines > best[0]:
                best = (lines, name, path.relative_to(root).as_posix())
    return best


def main():
    root = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent
    print("files and lines per top folder")
    total_files = total_lines = 0
    for top in TOP_FOLDERS:
        files = [p for p in (root / top).rglob("*") if p.is_file() and p.suffix in SOURCE_SUFFIXES]
        lines = sum(len(p.read_text(errors="replace").splitlines()) for p in files)
        total_files += len(files)
        total_lines += lines
        print(f"  {top + '/':<10} {len(files):5d} files {lines:7d} lines")
    print(f"  {'total':<10} {total_files:5d} files {total_lines:7d} lines")

    code = [p for p in include_graph.source_files(root)]
    lines, name, where = largest(CLASS_HEAD, code, root)
    print(f"\nlargest class:    {name} ({where}), {lines} lines")
    lines, name, where = largest(FUNCTION_HEAD, [p for p in code if p.suffix in (".cpp", ".cc")], root,
                                 NOT_FUNCTIONS)
    print(f"largest function: {name} ({where}), {lines} lines")

    print("\ninclude arrows between folders")
    arrows, upward = include_graph.include_arrows(root)
    include_graph.print_table(arrows)
    print(f"  {sum(c for (s, t), c in arrows.items() if s != t)} includes across folders, {len(upward)} upward")

    print("\ncasts (engine/, contact/, fem/, tools/)")
    body_cast = re.compile(r"static_cast<\s*(?:const\s+)?(?:csim::)?(" + "|".join(BODY_TYPES) + r")\b")
    dynamic = static = 0
    for path in code:
        text = strip_comments_and_strings(path.read_text(errors="replace"))
        dynamic += len(re.findall(r"\bdynamic_cast\b", text))
        static += len(body_cast.findall(text))
    print(f"  dynamic_cast:               {dynamic}")
    print(f"  static_cast<> to body types: {static}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
