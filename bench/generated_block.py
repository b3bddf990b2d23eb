"""The generated block of a hand-written document: only the text between two markers is replaced, so
the prose around it survives a regeneration. The file is replaced whole (written aside, then renamed)."""
import os
import sys


def replace_block(path, begin, end, lines):
    text = open(path).read()
    if begin not in text or end not in text:
        sys.exit(f"{path}: no '{begin}' ... '{end}' block to replace")
    head, rest = text.split(begin, 1)
    tail = rest.split(end, 1)[1]
    with open(path + ".tmp", "w") as f:
        f.write(head + "\n".join([begin] + lines + [end]) + tail)
    os.replace(path + ".tmp", path)
