#!/usr/bin/env python3
"""Prints the longest functions of raster's C++ sources, lambdas among them.

    raster/tools/longest_functions.py [PATH ...] [--top N]

PATHs are files or directories (searched for .cpp, .hpp, .h, .cc, .cxx, .hh, .inl, .ipp); without
any, the library's rooms (raster/pipeline, raster/lecture, raster/tooling) and raster/tools of this checkout. Prints the N (default 10) longest,
longest first, one a line: length in lines, file:line of the definition's first line, and its name
("Class::method", "lambda in Class::method", "lambda at file scope").

A function's length counts the lines from its definition's first line (its template header or
return type, after the comments before it) to the line of its closing brace, both included.

No compiler is involved: a scanner that knows comments, string, character and raw string literals,
digit separators and preprocessor lines matches the braces, and each opening brace is classified
by the code before it (a parameter list, a lambda's capture, a class, a control statement, an
initializer). Code the preprocessor hides or duplicates (#if branches that each open a brace) can
unbalance the braces: such a file gets a warning on stderr, and what was matched is kept.

Exit status: 0 listed; 2 a bad command line or a path that does not exist.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
from dataclasses import dataclass

SOURCE_SUFFIXES = (".cpp", ".hpp", ".h", ".cc", ".cxx", ".hh", ".inl", ".ipp")
DEFAULT_DIRS = ("raster/pipeline", "raster/lecture", "raster/tooling", "raster/tools")

# Keywords after which a parenthesised group opens a statement's block, not a function.
CONTROL_KEYWORDS = {"if", "for", "while", "switch", "catch", "constexpr", "consteval", "return", "co_return"}
# Keywords whose parenthesised group is part of a type or a qualifier, not a parameter list.
NOT_PARAMETERS = {"decltype", "noexcept", "alignas", "sizeof", "alignof", "requires", "__attribute__",
                  "throw", "static_assert", "typeid", "__declspec", "explicit"}
# What may follow a function's parameter list before its body.
QUALIFIERS = {"const", "volatile", "noexcept", "override", "final", "mutable", "constexpr", "consteval",
              "static", "try", "&", "&&"}
SCOPE_KEYWORDS = {"class", "struct", "union", "enum", "namespace"}
LABELS = {"public", "private", "protected", "default"}


@dataclass
class Function:
    path: str
    line: int  # of the definition's first line
    end_line: int  # of its closing brace
    name: str
    is_lambda: bool

    @property
    def length(self) -> int:
        return self.end_line - self.line + 1


def blank_code(text: str) -> str:
    """The text with comments, literals' contents and preprocessor lines replaced by spaces.

    Line breaks stay where they were, so offsets and line numbers are the original's. A string or
    character literal keeps its quotes (an empty "" or ''), so the code around it still reads.
    """
    out = list(text)
    n = len(text)
    i = 0
    line_start = True  # nothing but white space since the last line break

    def blank(start: int, end: int) -> None:
        for k in range(start, min(end, n)):
            if out[k] != "\n":
                out[k] = " "

    while i < n:
        c = text[i]
        if c == "\n":
            line_start = True
            i += 1
            continue
        if c in " \t\r\f\v":
            i += 1
            continue
        if line_start and c == "#":
            end = preprocessor_end(text, i)
            blank(i, end)
            i = end
            continue
        line_start = False
        if text.startswith("//", i):
            end = text.find("\n", i)
            end = n if end < 0 else end
            blank(i, end)
            i = end
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            blank(i, end)
            i = end
        elif c == '"':
            raw = re.search(r'(?:u8|u|U|L)?R$', text[max(0, i - 3):i])
            if raw and not is_identifier_char(text, i - len(raw.group(0)) - 1):
                end = raw_string_end(text, i)
            else:
                end = quoted_end(text, i, '"')
            blank(i + 1, end - 1)
            i = end
        elif c == "'":
            if is_digit_separator(text, i):
                out[i] = " "
                i += 1
                continue
            end = quoted_end(text, i, "'")
            blank(i + 1, end - 1)
            i = end
        else:
            i += 1
    return "".join(out)


def is_identifier_char(text: str, i: int) -> bool:
    return 0 <= i < len(text) and (text[i].isalnum() or text[i] == "_")


def is_digit_separator(text: str, i: int) -> bool:
    """Whether the quote at i separates digits (1'000'000) rather than opening a character literal."""
    k = i
    while k > 0 and (text[k - 1].isalnum() or text[k - 1] in "_."):
        k -= 1
    return k < i and text[k].isdigit()


def preprocessor_end(text: str, i: int) -> int:
    """The end of the directive starting at i: its line, and the next ones while a line ends in \\."""
    n = len(text)
    while True:
        end = text.find("\n", i)
        if end < 0:
            return n
        # A block comment that starts on the directive's line may run past it.
        line = text[i:end]
        comment = line.find("/*")
        if comment >= 0 and "*/" not in line[comment + 2:]:
            close = text.find("*/", i + comment + 2)
            if close < 0:
                return n
            i = close + 2
            continue
        if line.rstrip("\r").endswith("\\"):
            i = end + 1
            continue
        return end


def quoted_end(text: str, i: int, quote: str) -> int:
    """The offset just past the literal opened at i, escapes followed; at most to the line's end."""
    n = len(text)
    k = i + 1
    while k < n:
        if text[k] == "\\":
            k += 2
            continue
        if text[k] == quote:
            return k + 1
        if text[k] == "\n":  # an unterminated literal: stop at the line's end
            return k
        k += 1
    return n


def raw_string_end(text: str, i: int) -> int:
    """The offset just past R"delim( ... )delim" whose quote is at i."""
    open_paren = text.find("(", i + 1)
    if open_paren < 0 or open_paren - i - 1 > 16:
        return quoted_end(text, i, '"')
    delimiter = text[i + 1:open_paren]
    close = text.find(")" + delimiter + '"', open_paren + 1)
    return len(text) if close < 0 else close + len(delimiter) + 2


# ---- Tokens of the code before an opening brace --------------------------------------------------

TOKEN = re.compile(r"\s*(::|->|&&|\|\||<<|>>|<=|>=|==|!=|[A-Za-z_][A-Za-z_0-9]*|\d[\w.']*|\S)")
PAIRS = {"(": ")", "[": "]", "{": "}"}


@dataclass
class Token:
    text: str  # for a group, its opening bracket
    offset: int  # in the file
    group: list | None = None  # a bracketed group's tokens, brackets excluded


def tokenize(code: str, start: int, end: int) -> list[Token]:
    """The tokens of code[start:end], each bracketed group as one Token (unbalanced ones dropped)."""
    stack: list[list[Token]] = [[]]
    openers: list[Token] = []
    pos = start
    while pos < end:
        m = TOKEN.match(code, pos, end)
        if not m:
            break
        pos = m.end()
        text, offset = m.group(1), m.start(1)
        if text in PAIRS:
            token = Token(text, offset, [])
            stack[-1].append(token)
            openers.append(token)
            stack.append(token.group)
        elif text in (")", "]", "}"):
            if openers and PAIRS[openers[-1].text] == text:
                openers.pop()
                stack.pop()
            # an unmatched closer: ignored
        else:
            stack[-1].append(Token(text, offset))
    return stack[0]


def is_group(token: Token | None, bracket: str) -> bool:
    return token is not None and token.group is not None and token.text == bracket


def is_attribute(token: Token) -> bool:
    """[[...]]: an attribute, not a lambda's capture list."""
    return is_group(token, "[") and len(token.group) == 1 and is_group(token.group[0], "[")


def strip_labels(tokens: list[Token]) -> list[Token]:
    """Drops access specifiers and case labels before the declaration (`public:`, `case 3:`)."""
    while tokens:
        if len(tokens) >= 2 and tokens[0].text in LABELS and tokens[1].text == ":":
            tokens = tokens[2:]
        elif tokens[0].text == "case":
            colon = next((k for k, t in enumerate(tokens) if t.text == ":"), None)
            if colon is None:
                return tokens
            tokens = tokens[colon + 1:]
        else:
            return tokens
    return tokens


def strip_template_header(tokens: list[Token]) -> list[Token]:
    """Drops `template <...>` (whose `class T` names no class) from the front."""
    while len(tokens) >= 2 and tokens[0].text == "template" and tokens[1].text == "<":
        depth = 0
        for k, t in enumerate(tokens[1:], start=1):
            depth += {"<": 1, ">": -1, ">>": -2}.get(t.text, 0)
            if depth <= 0:
                tokens = tokens[k + 1:]
                break
        else:
            return tokens
    return tokens


def qualifiers_only(tokens: list[Token]) -> bool:
    """Whether what follows a parameter list can end a function's declarator before its body."""
    k = 0
    while k < len(tokens):
        t = tokens[k]
        if t.text in ("->", "requires"):
            return True  # a trailing return type or a constraint: anything may follow
        takes_group = t.text in ("noexcept", "__attribute__", "throw")
        if takes_group and k + 1 < len(tokens) and is_group(tokens[k + 1], "("):
            k += 2
        elif t.text in QUALIFIERS or is_attribute(t):
            k += 1
        else:
            return False
    return True


def parameter_list(tokens: list[Token]) -> tuple[int | None, bool]:
    """Where the parameter list is among the tokens before a function's body, if there is one, and
    whether member initializers follow it (a constructor's `Name(params) : member(x), other{y}`)."""
    for k, t in enumerate(tokens):
        if t.text == ":" and t.group is None:
            j = k - 1
            while j >= 0 and not is_group(tokens[j], "(") and (tokens[j].text in QUALIFIERS):
                j -= 1
            if j >= 1 and is_group(tokens[j], "(") and qualifiers_only(tokens[j + 1:k]):
                return j, True
            break  # a colon of something else (a base clause, a bit field): no initializers
    for k in range(len(tokens) - 1, -1, -1):
        if not is_group(tokens[k], "("):
            continue
        if k > 0 and tokens[k - 1].text in NOT_PARAMETERS:
            continue
        return (k if qualifiers_only(tokens[k + 1:]) else None), False
    return None, False


def function_name(tokens: list[Token]) -> str | None:
    """The (qualified) name before a parameter list, or None when it is not a function's."""
    if not tokens:
        return None
    last = tokens[-1]
    k = len(tokens) - 1
    # operator(), operator==, operator new: `operator` within the last few tokens.
    for j in range(max(0, k - 3), k + 1):
        if tokens[j].text == "operator":
            parts = ["()" if is_group(t, "(") else ("[]" if is_group(t, "[") else t.text)
                     for t in tokens[j + 1:]]
            word = bool(parts) and re.match(r"[A-Za-z_]", parts[0]) is not None  # operator bool, operator new
            return qualified(tokens, j, "operator" + (" " if word else "") + "".join(parts))
    if last.group is not None or not re.match(r"[A-Za-z_]", last.text):
        if last.text == ">":  # a template's explicit specialization: name<args>(...)
            depth, j = 0, k
            while j >= 0:
                depth += {">": 1, "<": -1}.get(tokens[j].text, 0)
                if depth == 0:
                    break
                j -= 1
            if j >= 1 and re.match(r"[A-Za-z_]", tokens[j - 1].text):
                return qualified(tokens, j - 1, tokens[j - 1].text)
        return None
    if last.text in CONTROL_KEYWORDS or last.text in NOT_PARAMETERS:
        return None
    name = last.text
    if k > 0 and tokens[k - 1].text == "~":
        return qualified(tokens, k - 1, "~" + name)
    return qualified(tokens, k, name)


def qualified(tokens: list[Token], k: int, name: str) -> str:
    """name preceded by the Scope:: qualifiers before tokens[k] (template arguments dropped)."""
    j = k - 1
    while j >= 1 and tokens[j].text == "::":
        scope = tokens[j - 1]
        if scope.text == ">":  # Scope<T>::name
            depth = 0
            while j >= 1:
                j -= 1
                depth += {">": 1, "<": -1}.get(tokens[j].text, 0)
                if depth == 0:
                    break
            scope = tokens[j - 1] if j >= 1 else scope
        if not re.match(r"[A-Za-z_]", scope.text):
            break
        name = scope.text + "::" + name
        j = tokens.index(scope) - 1
    return name


def is_lambda_capture(tokens: list[Token], k: int) -> bool:
    """Whether tokens[k] is a lambda's [captures] (not an attribute nor a subscript)."""
    t = tokens[k]
    if not is_group(t, "[") or is_attribute(t):
        return False
    before = tokens[k - 1] if k > 0 else None
    if before is None or before.text in ("return", "co_return", "co_yield", "throw", "else", "do"):
        return True
    return not (re.match(r"[A-Za-z_0-9]", before.text) or is_group(before, "(") or is_group(before, "["))


def classify(tokens: list[Token]) -> tuple[str, str]:
    """What an opening brace whose code before it is `tokens` opens: (kind, name).

    kind: "function", "lambda", "scope" (a class, namespace, enum: name for a class), "block" (a
    statement's body, a bare block) or "init" (a braced initializer).
    """
    tokens = strip_labels(tokens)
    if not tokens:
        return "block", ""
    last = tokens[-1]
    if last.text in ("else", "do") or (last.text == "try" and len(tokens) == 1):
        return "block", ""
    params, initializers = parameter_list(tokens)
    if initializers and last.group is None and last.text != "...":
        return "init", ""  # a member's braced initializer: `: member{`
    if params is not None:
        before = tokens[:params]
        # [captures](params), [captures]<template params>(params)
        k = params - 1
        if k >= 0 and tokens[k].text == ">":
            depth = 0
            while k >= 0:
                depth += {">": 1, "<": -1}.get(tokens[k].text, 0)
                if depth == 0:
                    break
                k -= 1
            k -= 1
        if k >= 0 and is_lambda_capture(tokens, k):
            return "lambda", ""
        if before and before[-1].text in CONTROL_KEYWORDS:
            return "block", ""
        name = function_name(before)
        if name is not None:
            if re.fullmatch(r"[A-Z][A-Z0-9_]*", name):  # a macro's: TEST(Suite, Name)
                name += "(" + "".join(", " if t.text == "," else t.text for t in tokens[params].group) + ")"
            return "function", name
    elif is_lambda_capture(tokens, len(tokens) - 1):
        return "lambda", ""
    tokens = strip_template_header(tokens)
    for k, t in enumerate(tokens):
        if t.text in SCOPE_KEYWORDS:
            names = [u.text for u in tokens[k + 1:] if re.match(r"[A-Za-z_]", u.text) and u.group is None
                     and u.text not in ("class", "struct", "final", "alignas")]
            return "scope", (names[0] if names and t.text in ("class", "struct", "union") else "")
        if t.text == "extern" and k + 1 < len(tokens) and tokens[k + 1].text == '"':
            return "scope", ""
    return "init", ""


# ---- The file's braces ------------------------------------------------------------------------------------


def scan(path: str, text: str, warn=None) -> list[Function]:
    """Every function and lambda defined in `text` (the contents of `path`)."""
    code = blank_code(text)
    line_starts = [0] + [m.end() for m in re.finditer("\n", code)]

    def line_of(offset: int) -> int:
        lo, hi = 0, len(line_starts) - 1
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if line_starts[mid] <= offset:
                lo = mid
            else:
                hi = mid - 1
        return lo + 1

    functions: list[Function] = []
    # Open brackets: (bracket, kind, name, start offset); and per open bracket, where the code of the
    # next declaration or statement starts.
    stack: list[tuple[str, str, str, int]] = []
    header_start = [0]
    for m in re.finditer(r"[{}()\[\];:]", code):
        c, pos = m.group(0), m.start()
        if c in "([":
            stack.append((c, "", "", pos))
            header_start.append(pos + 1)
        elif c == "{":
            tokens = tokenize(code, header_start[-1], pos)
            kind, name = classify(tokens)
            if kind in ("function", "lambda"):
                start = strip_labels(tokens)
                first = start[0].offset if start and kind == "function" else pos
                if kind == "lambda":
                    first, variable = lambda_start(tokens, pos)
                scopes = [s[2] for s in stack if s[1] == "scope" and s[2]]
                if kind == "function" and scopes and "::" not in name:
                    name = scopes[-1] + "::" + name
                if kind == "lambda":
                    # In the innermost function, else class; named after the variable it initializes.
                    enclosing = next((s[2] for s in reversed(stack) if s[1] == "function"), None)
                    enclosing = enclosing or (scopes[-1] if scopes else None)
                    name = "lambda" + (" " + variable if variable else "")
                    name += " in " + enclosing if enclosing else " at file scope"
                stack.append(("{", kind, name, first))
            else:
                stack.append(("{", kind, name, pos))
            header_start.append(pos + 1)
        elif c in ")]}":
            opener = {")": "(", "]": "[", "}": "{"}[c]
            if not stack or stack[-1][0] != opener:
                if warn:
                    warn(f"{path}:{line_of(pos)}: unmatched '{c}'; braces after it may be misread")
                continue
            bracket, kind, name, first = stack.pop()
            header_start.pop()
            if kind in ("function", "lambda"):
                functions.append(Function(path, line_of(first), line_of(pos), name, kind == "lambda"))
            if c == "}" and kind != "init":
                header_start[-1] = pos + 1  # the next declaration starts after a body
        elif c == ";":
            header_start[-1] = pos + 1
        elif c == ":":
            # After a label (public:, case 1:, default:) a new statement or declaration starts.
            if code[pos - 1:pos] != ":" and code[pos + 1:pos + 2] != ":":
                label = code[header_start[-1]:pos].split()
                if label and (label[0] in ("case",) or (len(label) == 1 and label[0] in LABELS)):
                    header_start[-1] = pos + 1
    if stack and warn:
        bracket, kind, name, first = stack[-1]
        warn(f"{path}:{line_of(first)}: '{bracket}' not closed by the end of the file")
    return functions


def lambda_start(tokens: list[Token], brace: int) -> tuple[int, str]:
    """The offset of the capture list of the lambda whose body opens at `brace`, and the variable it
    initializes (`auto emit = [&](...) {`: "emit"), if any."""
    for k in range(len(tokens) - 1, -1, -1):
        if is_lambda_capture(tokens, k):
            variable = ""
            if k >= 2 and tokens[k - 1].text == "=" and re.match(r"[A-Za-z_]", tokens[k - 2].text):
                variable = tokens[k - 2].text
            return tokens[k].offset, variable
    return brace, ""


# ---- Command line ---------------------------------------------------------------------------------------


def source_files(paths: list[str]) -> list[str]:
    files = []
    for path in paths:
        if os.path.isfile(path):
            files.append(path)
            continue
        for root, dirs, names in os.walk(path):
            dirs.sort()
            files.extend(os.path.join(root, n) for n in sorted(names) if n.endswith(SOURCE_SUFFIXES))
    return files


def display_path(path: str) -> str:
    relative = os.path.relpath(path)
    return path if relative.startswith("..") else relative


def positive(value: str) -> int:
    if not re.fullmatch(r"\d+", value) or int(value) < 1:
        raise argparse.ArgumentTypeError(f"'{value}' is not a whole number of at least 1")
    return int(value)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="longest_functions.py",
        description="The longest functions and lambdas of C++ sources, with file:line and length in lines.")
    parser.add_argument("paths", nargs="*", metavar="PATH",
                        help="files or directories (default: raster/pipeline, raster/lecture, raster/tooling, raster/tools)")
    parser.add_argument("--top", type=positive, default=10, metavar="N", help="how many to list (default 10)")
    args = parser.parse_args(argv)
    paths = args.paths
    if not paths:
        root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
        paths = [os.path.join(root, d) for d in DEFAULT_DIRS]
    missing = [p for p in paths if not os.path.exists(p)]
    if missing:
        parser.error("no such file or directory: " + ", ".join(missing))

    def warn(message: str) -> None:
        print(f"longest_functions.py: warning: {message}", file=sys.stderr)

    functions: list[Function] = []
    for path in source_files(paths):
        try:
            with open(path, encoding="utf-8", errors="replace") as f:
                text = f.read()
        except OSError as e:
            warn(f"{path}: {e.strerror}")
            continue
        functions.extend(scan(display_path(path), text, warn))
    functions.sort(key=lambda f: (-f.length, f.path, f.line))
    for f in functions[:args.top]:
        print(f"{f.length:5d}  {f.path}:{f.line}  {f.name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
