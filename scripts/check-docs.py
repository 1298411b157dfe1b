#!/usr/bin/python3
"""Check the Markdown documentation without a network: every relative link in README.md,
CHANGELOG.md and docs/*.md resolves (the file exists; a #fragment names a heading of the
target page), and every fenced code block parses (sh/bash/shell: `bash -n`; json:
json.loads, a fragment such as `"time": {...}` is tried inside braces).

    /usr/bin/python3 scripts/check-docs.py [REPO_ROOT]

Prints one line per problem (file:line: what) and exits 1 if there is any.
"""
import json
import os
import re
import subprocess
import sys

root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
pages = [os.path.join(root, "README.md"), os.path.join(root, "CHANGELOG.md")]
pages += sorted(os.path.join(root, "docs", f) for f in os.listdir(os.path.join(root, "docs")) if f.endswith(".md"))
pages = [p for p in pages if os.path.exists(p)]

FENCE = re.compile(r"^(\s*)(`{3,}|~{3,})\s*([^\s`]*)")
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def slug(title):
    """Heading anchors as GitHub and MyST (heading_anchors) make them."""
    title = re.sub(r"`([^`]*)`", r"\1", title)
    title = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", title)
    return re.sub(r"[^\w\- ]", "", title.strip().lower()).replace(" ", "-")


def split(path):
    """(text lines outside code blocks with their numbers, code blocks (lang, first line, text))."""
    prose, blocks, fence = [], [], None
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    for i, line in enumerate(lines, 1):
        m = FENCE.match(line)
        if fence is None:
            if m:
                fence, lang, start, body = m.group(2), m.group(3).lower(), i, []
                continue
            prose.append((i, line))
        elif m and m.group(2).startswith(fence) and not m.group(3):
            blocks.append((lang, start, "\n".join(body)))
            fence = None
        else:
            body.append(line)
    return prose, blocks


anchors_cache = {}


def anchors(path):
    if path not in anchors_cache:
        prose, _ = split(path)
        found = set()
        for _, line in prose:
            m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
            if m:
                s = slug(m.group(1))
                k, name = 1, s
                while name in found:  # repeated headings get -1, -2, ...
                    name = "%s-%d" % (s, k)
                    k += 1
                found.add(name)
            for a in re.findall(r"\(([\w-]+)\)=\s*$", line):  # MyST targets (label)=
                found.add(a)
        anchors_cache[path] = found
    return anchors_cache[path]


problems = []
n_links = n_blocks = 0
for page in pages:
    rel = os.path.relpath(page, root)
    prose, blocks = split(page)
    for lineno, line in prose:
        for target in LINK.findall(re.sub(r"`[^`]*`", "", line)):
            if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):  # http:, mailto:, ...
                continue
            n_links += 1
            path, _, frag = target.partition("#")
            dest = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
            if not os.path.exists(dest):
                problems.append("%s:%d: link target %s does not exist" % (rel, lineno, target))
            elif frag and dest.endswith(".md") and frag not in anchors(dest):
                problems.append("%s:%d: no heading #%s in %s" % (rel, lineno, frag, os.path.relpath(dest, root)))
    for lang, start, text in blocks:
        if lang in ("sh", "bash", "shell", "console"):
            n_blocks += 1
            if lang == "console":  # prompts: check the commands after "$ "
                text = "\n".join(l[2:] for l in text.split("\n") if l.startswith("$ "))
            r = subprocess.run(["bash", "-n"], input=text, text=True, capture_output=True)
            if r.returncode != 0:
                problems.append("%s:%d: shell block does not parse: %s" % (rel, start, r.stderr.strip().replace("\n", " | ")))
        elif lang == "json":
            n_blocks += 1
            try:
                json.loads(text)
            except ValueError as e:
                try:
                    json.loads("{" + text + "}")
                except ValueError:
                    problems.append("%s:%d: JSON block does not parse: %s" % (rel, start, e))

for p in problems:
    print(p)
print("check-docs: %d pages, %d relative links, %d code blocks checked, %d problems"
      % (len(pages), n_links, n_blocks, len(problems)))
sys.exit(1 if problems else 0)
