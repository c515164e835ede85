#!/usr/bin/env python3
"""Checks the relative links of README.md and docs/**/*.md (docs/results/ aside): each must
name a file that exists and, after '#', a heading of that file (GitHub's anchors). Prints
every broken link as file:line and exits 1 if there is one.

    python3 scripts/check-doc-links.py
"""

import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")


def anchors(path):
    """GitHub's anchors of a Markdown file's headings (outside code fences)."""
    found, seen, fenced = set(), {}, False
    for line in path.read_text().splitlines():
        if line.lstrip().startswith("```"):
            fenced = not fenced
        if fenced or not line.startswith("#"):
            continue
        text = line.lstrip("#").strip().lower()
        slug = re.sub(r"[^\w\- ]", "", text).replace(" ", "-")
        n = seen.get(slug, 0)
        seen[slug] = n + 1
        found.add(slug if n == 0 else f"{slug}-{n}")
    return found


def main():
    files = [ROOT / "README.md"] + [
        p for p in sorted((ROOT / "docs").rglob("*.md")) if "results" not in p.relative_to(ROOT / "docs").parts
    ]
    broken = []
    for source in files:
        fenced = False
        for number, line in enumerate(source.read_text().splitlines(), 1):
            if line.lstrip().startswith("```"):
                fenced = not fenced
            if fenced:
                continue
            for target in LINK.findall(line):
                if re.match(r"[a-z]+:", target):
                    continue
                name, _, anchor = target.partition("#")
                path = (source.parent / name).resolve() if name else source
                where = f"{source.relative_to(ROOT)}:{number}: {target}"
                if not path.exists():
                    broken.append(f"{where} (no such file)")
                elif anchor and path.suffix == ".md" and anchor not in anchors(path):
                    broken.append(f"{where} (no such heading)")
    print("\n".join(broken) or f"{len(files)} files, every relative link resolves")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
