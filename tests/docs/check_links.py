#!/usr/bin/env python3
"""Every relative link in the repository's documentation resolves inside the repository.

Checks README.md, docs/*.md and every other README.md: each [text](target) outside code must name
an existing file or folder (relative to the document) that lies inside the repository, and a
#fragment on a Markdown target must be one of that file's headings (GitHub's anchor rule). No
document may point at the shared data folder beside a checkout (a user's clone has none).
Usage: check_links.py REPO_ROOT. Exit 1 listing every broken link, one per line.
"""
import os
import re
import sys

LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")


def prose(text):
    """The text with fenced blocks and inline code blanked out, line numbers kept."""
    text = re.sub(r"^```.*?^```", lambda m: "\n" * m.group(0).count("\n"), text,
                  flags=re.S | re.M)
    return re.sub(r"`[^`\n]*`", "", text)


def anchors(path):
    # GitHub: lower case, drop everything but letters, digits, spaces, hyphens and underscores,
    # spaces become hyphens; a repeated heading gets -1, -2, ...
    seen, out = {}, set()
    for line in prose(open(path, encoding="utf-8").read()).splitlines():
        m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if not m:
            continue
        slug = re.sub(r"[^\w\- ]", "", m.group(1).lower()).replace(" ", "-")
        n = seen.get(slug, 0)
        seen[slug] = n + 1
        out.add(slug if n == 0 else f"{slug}-{n}")
    return out


def documents(root):
    yield os.path.join(root, "README.md")
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames[:] = [d for d in dirnames if not d.startswith(".") and d not in ("build", "dist")]
        rel = os.path.relpath(dirpath, root)
        for f in sorted(filenames):
            if f.endswith(".md") and (rel == "docs" or (f == "README.md" and rel != ".")):
                yield os.path.join(dirpath, f)


def main():
    root = os.path.realpath(sys.argv[1])
    errors = []
    count = 0
    for doc in documents(root):
        name = os.path.relpath(doc, root)
        text = open(doc, encoding="utf-8").read()
        if "../shared" in text:
            errors.append(f"{name}: names ../shared, which a clone does not have")
        for lineno, line in enumerate(prose(text).splitlines(), 1):
            for target in LINK.findall(line):
                if re.match(r"^[a-z]+:", target):
                    continue
                count += 1
                path, _, frag = target.partition("#")
                full = os.path.realpath(os.path.join(os.path.dirname(doc), path)) if path else doc
                where = f"{name}:{lineno}: {target}"
                if not (full == root or full.startswith(root + os.sep)):
                    errors.append(f"{where}: outside the repository")
                elif not os.path.exists(full):
                    errors.append(f"{where}: no such file")
                elif frag and full.endswith(".md") and frag not in anchors(full):
                    errors.append(f"{where}: no heading #{frag}")
    for e in errors:
        print(e)
    print(f"{count} links checked, {len(errors)} broken", file=sys.stderr)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
