#!/usr/bin/env python3
"""Checks the repository's Markdown links: every relative link of every
tracked .md file (README, the guide, docs/, scripts/, crates' READMEs) names a
file or directory that exists, and every #anchor names a heading of its
target; every page of the guide is in its SUMMARY.md and every SUMMARY.md
entry is a page. Links to other sites are not followed (CI stays offline
there). Prints each broken link as FILE:LINE: LINK (why) and exits 1 if any.

    python3 .ci/check-links.py
"""
import os
import re
import subprocess
import sys

LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
FENCE = re.compile(r"^\s*(```|~~~)")


def slug(heading):
    """GitHub's and mdBook's anchor of a heading."""
    text = re.sub(r"[`*_]|\[([^\]]*)\]\([^)]*\)", r"\1", heading.strip().lower())
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def headings(path, cache={}):
    """The anchors of a Markdown file's headings."""
    if path not in cache:
        anchors, fenced = set(), False
        with open(path, encoding="utf-8") as f:
            for line in f:
                if FENCE.match(line):
                    fenced = not fenced
                elif not fenced and line.startswith("#"):
                    base = slug(line.lstrip("#"))
                    anchor, n = base, 1
                    while anchor in anchors:
                        anchor, n = f"{base}-{n}", n + 1
                    anchors.add(anchor)
        cache[path] = anchors
    return cache[path]


def links(path):
    """(line number, link) of every Markdown link outside code blocks."""
    fenced = False
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if FENCE.match(line):
                fenced = not fenced
                continue
            if fenced:
                continue
            for match in LINK.finditer(re.sub(r"`[^`]*`", "", line)):
                yield number, match.group(1)


def broken(path, link):
    """Why a link of `path` is broken, or None."""
    if re.match(r"^[a-z][a-z0-9+.-]*:", link):
        return None  # another site, mail: not followed
    target, _, anchor = link.partition("#")
    resolved = os.path.normpath(os.path.join(os.path.dirname(path), target)) if target else path
    if not os.path.exists(resolved):
        return "no such file"
    if anchor and resolved.endswith(".md") and anchor not in headings(resolved):
        return f"no heading #{anchor} in {resolved}"
    return None


def summary_problems(book="docs/guide/src"):
    """Pages of the guide missing from SUMMARY.md, and entries with no page."""
    listed = {link.partition("#")[0] for _, link in links(os.path.join(book, "SUMMARY.md"))}
    pages = {
        os.path.relpath(os.path.join(d, f), book)
        for d, _, files in os.walk(book)
        for f in files
        if f.endswith(".md") and f != "SUMMARY.md"
    }
    return [f"{book}/{p}: not in SUMMARY.md" for p in sorted(pages - listed)] + [
        f"{book}/SUMMARY.md: {p}: no such page" for p in sorted(listed - pages)
    ]


def main():
    os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    files = subprocess.run(
        ["git", "ls-files", "--cached", "--others", "--exclude-standard", "*.md"],
        check=True, capture_output=True, text=True,
    ).stdout.split()
    problems = [
        f"{path}:{number}: {link} ({why})"
        for path in files
        if os.path.exists(path)
        for number, link in links(path)
        if (why := broken(path, link))
    ] + summary_problems()
    for problem in problems:
        print(problem)
    print(f"{len(files)} Markdown files checked, {len(problems)} broken link(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
