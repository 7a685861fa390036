#!/usr/bin/env python3
"""Checks the links of ray's Markdown documentation: README.md and docs/*.md.

Every relative link or image, [text](path) or ![alt](path), must lead to a file or folder
of the checkout, and every #anchor (path.md#anchor, or #anchor alone for the same page)
to a heading of that page, named as GitHub names headings. Links in code (fenced blocks
and `inline code`) are not links; http(s) and mailto links are not followed.

Usage: doc_links.py SOURCE_DIR      (exit 1, naming each broken link, when any is broken)
"""
import re
import sys
from pathlib import Path

INLINE_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
FENCE = re.compile(r"^\s*(```|~~~)")
INLINE_CODE = re.compile(r"(`+)(?:(?!\1).)+?\1", re.S)


def outside_fences(markdown: str) -> str:
    """The text outside fenced code blocks, with lines kept in place."""
    lines, inside = [], False
    for line in markdown.split("\n"):
        if FENCE.match(line):
            inside = not inside
            lines.append("")
        else:
            lines.append("" if inside else line)
    return "\n".join(lines)


def prose(markdown: str) -> str:
    """The text outside code, fenced or inline, with lines kept in place."""
    return INLINE_CODE.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), outside_fences(markdown))


def github_anchor(heading: str) -> str:
    """GitHub's id for a heading: lower case, punctuation dropped, spaces made hyphens."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link's text only
    text = text.replace("`", "").strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path: Path) -> set:
    """The ids of a page's headings (a repeated one gets -1, -2, ... as on GitHub)."""
    seen, ids = {}, set()
    markdown = path.read_text(encoding="utf-8")
    for line in outside_fences(markdown).split("\n"):  # a heading's code is part of its name
        match = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if not match:
            continue
        base = github_anchor(match.group(1))
        count = seen.get(base, 0)
        seen[base] = count + 1
        ids.add(base if count == 0 else f"{base}-{count}")
    return ids


def broken_links(page: Path, root: Path) -> list:
    problems = []
    text = prose(page.read_text(encoding="utf-8"))
    for match in INLINE_LINK.finditer(text):
        target = match.group(1)
        line = text.count("\n", 0, match.start()) + 1
        where = f"{page.relative_to(root)}:{line}: {target}"
        if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):  # http:, https:, mailto:
            continue
        path_part, _, anchor = target.partition("#")
        linked = (page.parent / path_part).resolve() if path_part else page
        if root not in linked.parents and linked != root:
            problems.append(f"{where}: leads outside the checkout")
        elif not linked.exists():
            problems.append(f"{where}: no such file")
        elif anchor and linked.suffix == ".md" and anchor not in anchors(linked):
            problems.append(f"{where}: no heading with the anchor #{anchor} in {linked.relative_to(root)}")
    return problems


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__.strip().split("\n")[-1])
        return 2
    root = Path(sys.argv[1]).resolve()
    pages = [root / "README.md"] + sorted((root / "docs").glob("*.md"))
    problems, links = [], 0
    for page in pages:
        links += len(INLINE_LINK.findall(prose(page.read_text(encoding="utf-8"))))
        problems += broken_links(page, root)
    for problem in problems:
        print(f"FAIL: {problem}")
    print(f"doc_links: {len(pages)} pages, {links} links, {len(problems)} broken")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
