#!/usr/bin/env python3
"""Writes a section of the verification notes: the text of FILE, a section beginning with
"## TITLE", replaces that section (up to the next "## " heading) in doc/verification.md and in
src/verify/findings.md (the notes scripts/verify appends to the doc it generates), so a study's
figures survive the doc's regeneration. Where the section is missing it goes before "## BEFORE"
when given and present, else at the end.

    scripts/verification-section.py FILE TITLE [BEFORE]
"""
import re
import sys

PATHS = ("doc/verification.md", "src/verify/findings.md")


def place(text, section, title, before):
    """Returns text with its section `title` replaced by `section` (or `section` inserted)."""
    m = re.search(r"^## " + re.escape(title) + r"\n.*?(?=^## |\Z)", text, flags=re.M | re.S)
    if m:
        return text[:m.start()] + section + text[m.end():]
    if before:
        b = re.search(r"^## " + re.escape(before) + r"$", text, flags=re.M)
        if b:
            return text[:b.start()] + section + text[b.start():]
    return text.rstrip("\n") + "\n\n" + section


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__.strip().splitlines()[-1].strip())
    section = open(sys.argv[1]).read()
    title = sys.argv[2]
    before = sys.argv[3] if len(sys.argv) == 4 else ""
    for path in PATHS:
        with open(path) as f:
            text = f.read()
        with open(path, "w") as f:
            f.write(place(text, section, title, before))


if __name__ == "__main__":
    main()
