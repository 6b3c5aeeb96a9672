#!/usr/bin/env python3
"""The documentation's links and the code's comments.

Every relative link of README.md, docs/, labs/ and slides/ (Markdown links and images, outside code) points
at a file or folder that exists, and where it names a heading (`FILE.md#heading`, or `#heading` in
the same file), at a heading that exists, spelt as GitHub spells anchors. No source file under
CODE_ROOTS cites an issue by its number or a commit of this repository's history: comments cite the
rule or the test.

    python3 tests/docs_links_test.py
"""

import os
import re
import subprocess
import sys
import unittest

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

# Markdown files whose links are checked: the README, and every .md under these folders (the decks'
# npm packages under slides/node_modules are not ours).
DOC_ROOTS = ["docs", "labs", "slides"]
DOC_SKIP_DIRS = {"node_modules"}
# Source trees whose text may name no issue and no commit; corpora and image data are skipped.
CODE_ROOTS = ["raster", "tests", "labs", "solutions", ".ci"]
CODE_FILES = ["CMakeLists.txt", "CMakePresets.json"]
CODE_SKIP_DIRS = {"corpus", "__pycache__"}
CODE_EXTENSIONS = {".cpp", ".hpp", ".h", ".py", ".sh", ".cmake", ".txt", ".json", ".gp", ""}

FENCE = re.compile(r"^(```|~~~).*?^\1[^\n]*$", re.MULTILINE | re.DOTALL)
# A code span: a run of backticks to the next run as long, within a paragraph (never across a blank line).
INLINE_CODE = re.compile(r"(`+)(?:(?!\1)(?!\n[ \t]*\n).)+?\1", re.DOTALL)
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
HEADING = re.compile(r"^ {0,3}(#{1,6})\s+(.*?)\s*#*\s*$", re.MULTILINE)
ISSUE = re.compile(r"\bissues?\s*#?\d+\b", re.IGNORECASE)
HEX_WORD = re.compile(r"(?<![.\w])(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,40}\b")


def strip_code(text):
    """The Markdown text with fenced blocks and inline code spans blanked out."""
    text = FENCE.sub(lambda m: "\n" * m.group(0).count("\n"), text)
    return INLINE_CODE.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)


def github_anchor(heading):
    """The anchor GitHub gives a heading: lower case, markup and punctuation dropped, spaces as '-'."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link's text stays
    text = text.replace("`", "").lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors_of(path, cache={}):
    """Every anchor of a Markdown file's headings, duplicates numbered as GitHub numbers them."""
    if path not in cache:
        with open(path, encoding="utf-8") as f:
            text = strip_code_fences_only(f.read())
        seen = {}
        result = set()
        for match in HEADING.finditer(text):
            anchor = github_anchor(match.group(2))
            count = seen.get(anchor, 0)
            seen[anchor] = count + 1
            result.add(anchor if count == 0 else f"{anchor}-{count}")
        cache[path] = result
    return cache[path]


def strip_code_fences_only(text):
    return FENCE.sub(lambda m: "\n" * m.group(0).count("\n"), text)


def markdown_files():
    files = [os.path.join(ROOT, "README.md")]
    for folder in DOC_ROOTS:
        for dirpath, dirnames, names in os.walk(os.path.join(ROOT, folder)):
            dirnames[:] = sorted(d for d in dirnames if d not in DOC_SKIP_DIRS)
            files += [os.path.join(dirpath, n) for n in sorted(names) if n.endswith(".md")]
    return files


def broken_links(path):
    """(line, target, why) for each relative link of one Markdown file that points nowhere."""
    with open(path, encoding="utf-8") as f:
        text = strip_code(f.read())
    problems = []
    for match in LINK.finditer(text):
        target = match.group(1)
        if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.IGNORECASE):  # http:, https:, mailto:
            continue
        line = text.count("\n", 0, match.start()) + 1
        file_part, _, anchor = target.partition("#")
        linked = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
        if not os.path.exists(linked):
            problems.append((line, target, "no such file"))
        elif anchor and linked.endswith(".md") and anchor not in anchors_of(linked):
            problems.append((line, target, f"no heading with anchor #{anchor} in {os.path.relpath(linked, ROOT)}"))
    return problems


def code_files():
    files = [os.path.join(ROOT, f) for f in CODE_FILES if os.path.exists(os.path.join(ROOT, f))]
    for folder in CODE_ROOTS:
        for dirpath, dirnames, names in os.walk(os.path.join(ROOT, folder)):
            dirnames[:] = sorted(d for d in dirnames if d not in CODE_SKIP_DIRS)
            for name in sorted(names):
                if os.path.splitext(name)[1] in CODE_EXTENSIONS:
                    files.append(os.path.join(dirpath, name))
    return files


def commits_among(words):
    """The words that name a commit of this repository (none where git or the history is absent)."""
    if not words:
        return set()
    try:
        out = subprocess.run(["git", "-C", ROOT, "cat-file", "--batch-check"], input="\n".join(words) + "\n",
                             capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        return set()
    if out.returncode != 0:
        return set()
    found = set()
    for word, line in zip(words, out.stdout.splitlines()):
        if line.split()[1:2] == ["commit"]:
            found.add(word)
    return found


class DocsLinks(unittest.TestCase):
    def test_every_relative_link_points_at_a_file_and_heading_that_exist(self):
        problems = []
        files = markdown_files()
        self.assertGreater(len(files), 5, "found too few Markdown files: is ROOT right?")
        for path in files:
            for line, target, why in broken_links(path):
                problems.append(f"{os.path.relpath(path, ROOT)}:{line}: ({target}) {why}")
        self.assertEqual(problems, [], "\n" + "\n".join(problems))

    def test_anchors_are_spelt_as_github_spells_them(self):
        self.assertEqual(github_anchor("Building: the first picture, the lab loop, CI"),
                         "building-the-first-picture-the-lab-loop-ci")
        self.assertEqual(github_anchor("Whole primitives behind a tile (`fastpath/depth_bounds.hpp`)"),
                         "whole-primitives-behind-a-tile-fastpathdepth_boundshpp")
        self.assertEqual(github_anchor("Shaders are functors, the pipeline is a template"),
                         "shaders-are-functors-the-pipeline-is-a-template")

    def test_a_broken_link_is_found(self):
        import tempfile
        with tempfile.TemporaryDirectory() as tmp:
            page = os.path.join(tmp, "page.md")
            with open(page, "w", encoding="utf-8") as f:
                f.write("# Title\n\n## A part\n\n[ok](page.md#a-part) [self](#title) [gone](missing.md)\n"
                        "[bad anchor](page.md#no-part) `[in code](nowhere.md)`\n\n```\n[fenced](x.md)\n```\n"
                        "[web](https://example.org/x.md)\n\nA lone ` backtick\nand [lost](lost.md)\n\n"
                        "[after](after.md) `a span\nover two lines` [kept](kept.md)\n")
            found = [(line, target) for line, target, _ in broken_links(page)]
        self.assertEqual(found, [(5, "missing.md"), (6, "page.md#no-part"), (14, "lost.md"), (16, "after.md"),
                                 (17, "kept.md")])


class NoHistoryInCode(unittest.TestCase):
    def test_no_source_file_names_an_issue_or_a_commit(self):
        problems = []
        candidates = {}
        for path in code_files():
            try:
                with open(path, encoding="utf-8") as f:
                    lines = f.read().splitlines()
            except UnicodeDecodeError:
                continue
            rel = os.path.relpath(path, ROOT)
            for number, line in enumerate(lines, 1):
                for match in ISSUE.finditer(line):
                    problems.append(f"{rel}:{number}: '{match.group(0)}': cite the rule or the test instead")
                for match in HEX_WORD.finditer(line):
                    candidates.setdefault(match.group(0), []).append(f"{rel}:{number}")
        commits = commits_among(sorted(candidates))
        for word in sorted(commits):
            for where in candidates[word]:
                problems.append(f"{where}: commit {word}: the history is git log's")
        self.assertEqual(problems, [], "\n" + "\n".join(problems))

    def test_the_patterns_find_what_they_should(self):
        # Spelt in pieces, so that this file does not match its own patterns.
        self.assertTrue(ISSUE.search("// raster grade (issue " + "32): grades"))
        self.assertTrue(ISSUE.search("issue #" + "33's goals"))
        self.assertFalse(ISSUE.search("corpus issue30_blend_feedback_overflow"))
        self.assertEqual(HEX_WORD.findall("(commit abc" + "1234) and 0xFFFF, 3.14159265f, deadbeef"), ["abc" + "1234"])


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1] + sys.argv[1:])
