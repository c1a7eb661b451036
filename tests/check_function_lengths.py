#!/usr/bin/python3
"""No function over 120 lines in src/, apps/ and python/src/ (issue 29): a long function is split by
stage, each stage a function named after what it does.

A heuristic parser (comments, strings and preprocessor lines blanked; braces matched) finds every function
and lambda body that is not inside another one and counts its lines, braces included. The test prints each
body over the limit that is not in KNOWN and fails if there is one; it also fails on a KNOWN entry that is
gone or now short enough (remove it from the list).
Usage: check_function_lengths.py [REPO] [--all]   (--all: list every body over the limit, known or not)
"""

import pathlib
import re
import sys

LIMIT = 120
ROOTS = ("src", "apps", "python/src")
# Known, listed so that no new one comes in; split them by stage and remove them here. None is left.
KNOWN: set[str] = set()

CONTROL = {"if", "for", "while", "switch", "catch", "return", "sizeof", "decltype", "alignof", "noexcept",
           "static_assert", "requires", "defined"}
WORD = re.compile(r"[A-Za-z_~][A-Za-z_0-9]*(?:::[A-Za-z_~][A-Za-z_0-9]*)*(?:\s*<[^<>;{}()]*>)?$")


def blank(text):
    """The text with comments, string and character literals and preprocessor lines turned to spaces
    (newlines kept, so that line numbers hold)."""
    out, i, n = [], 0, len(text)
    at_line_start = True
    while i < n:
        c = text[i]
        if at_line_start and c == "#":  # a preprocessor line, with its continuations
            j = i
            while j < n and not (text[j] == "\n" and text[j - 1] != "\\"):
                j += 1
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
            continue
        if c == "\n":
            at_line_start = True
        elif not c.isspace():
            at_line_start = False
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "R" and text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            k = text.find("(", i)
            end = ")" + text[i + 2:k] + '"'
            j = text.find(end, k)
            j = n if j < 0 else j + len(end)
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c in "\"'" and not (c == "'" and i > 0 and text[i - 1].isalnum()):  # 1'000 is a digit separator
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(" " * (min(j + 1, n) - i))
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def matching_paren(code, close):
    """Index of the '(' matching the ')' at \\p close."""
    depth = 0
    for k in range(close, -1, -1):
        if code[k] == ")":
            depth += 1
        elif code[k] == "(":
            depth -= 1
            if depth == 0:
                return k
    return -1


def body_name(code, brace):
    """The name of the function or lambda whose body opens at \\p brace, or None if it opens something else
    (a namespace, class, control statement, initializer list)."""
    head = code[max(0, brace - 2000):brace]
    # Cut at the statement before: the last ';', '{' or '}' outside parentheses.
    depth, start = 0, 0
    for k in range(len(head) - 1, -1, -1):
        ch = head[k]
        if ch == ")":
            depth += 1
        elif ch == "(":
            depth -= 1
        elif ch in ";{}" and depth <= 0:
            start = k + 1
            break
    head = head[start:]
    s = head.rstrip()
    # Trailing specifiers and a trailing return type: "const", "noexcept", "override", "-> T", "mutable".
    s = re.sub(r"(\s*(const|noexcept|override|final|mutable|constexpr|&|&&)\b)*\s*(->\s*[^(){};]+)?$", "", s).rstrip()
    # A constructor's member initializer list: ") : a_(x), b_{y}" — drop it back to the parameter list.
    m = re.search(r"\)\s*:\s*[A-Za-z_]", s)
    if m and not re.search(r"\?", s[m.end():]):
        s = s[:m.start() + 1]
    if not s.endswith(")"):
        return None
    open_ = matching_paren(s, len(s) - 1)
    if open_ < 0:
        return None
    before = s[:open_].rstrip()
    if before.endswith("]"):  # a lambda: [captures](params) {
        cap = before.rfind("[")
        lead = before[:cap].rstrip()
        assigned = re.search(r"([A-Za-z_][A-Za-z_0-9]*)\s*=\s*$", lead)
        return f"lambda {assigned.group(1)}" if assigned else "lambda"
    m = WORD.search(before)
    if not m:
        return None
    name = re.sub(r"\s*<.*$", "", m.group(0)).split("::")[-1]
    if name in CONTROL:
        return None
    return name


def long_bodies(path):
    code = blank(path.read_text(errors="replace"))
    stack = []  # (is_function, name, line of '{')
    out = []
    line = 1
    for i, ch in enumerate(code):
        if ch == "\n":
            line += 1
        elif ch == "{":
            inside = any(f for f, _, _ in stack)
            name = None if inside else body_name(code, i)
            stack.append((name is not None, name, line))
        elif ch == "}" and stack:
            is_function, name, first = stack.pop()
            if is_function and line - first + 1 > LIMIT:
                out.append((name, first, line - first + 1))
    return out


def scan(repo):
    found = {}
    for root in ROOTS:
        for path in sorted((repo / root).rglob("*")):
            if path.suffix not in (".cpp", ".h", ".inc"):
                continue
            rel = str(path.relative_to(repo))
            for name, first, lines in long_bodies(path):
                key = f"{rel}: {name.split()[0] if name.startswith('lambda') else name}"
                found.setdefault(key, []).append((first, lines, name))
    return found


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    repo = pathlib.Path(args[0] if args else pathlib.Path(__file__).resolve().parent.parent)
    if not (repo / "src").is_dir():
        print(f"{repo}: no src here", file=sys.stderr)
        return 2
    found = scan(repo)
    bad = 0
    for key, where in sorted(found.items()):
        for first, lines, name in where:
            known = key in KNOWN
            if not known or "--all" in sys.argv:
                print(f"{key.split(':')[0]}:{first}: {name}: {lines} lines (limit {LIMIT}){' (known)' if known else ''}")
            bad += not known
    stale = sorted(KNOWN - set(found))
    for key in stale:
        print(f"{key}: in KNOWN but no longer over {LIMIT} lines: remove it from the list")
    print(f"{bad} function(s) over {LIMIT} lines not in KNOWN, {len(stale)} stale KNOWN entr(ies), "
          f"{len(KNOWN) - len(stale)} known")
    return 1 if bad or stale else 0


if __name__ == "__main__":
    sys.exit(main())
