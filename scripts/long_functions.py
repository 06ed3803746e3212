#!/usr/bin/python3
"""List the library's function definitions longer than N lines (issue 48).

Reads every .cpp, .h and .hpp file under common/ (tests/ folders left out),
strips comments, string and character literals and preprocessor lines, and
matches braces. A brace at namespace or class scope opens
  - a namespace (named, anonymous, inline) or an extern "C" block: looked into;
  - a class, struct or union body: looked into, its member functions count;
  - a function body, when its declaration holds a parameter list: the whole
    body is the function, lambdas and local classes in it included;
  - anything else (an enum, an initializer, a constructor's braced member
    initializer): skipped.
A function's length runs from the line of its name to its closing brace,
both counted.

Prints `path:line: name (N lines)` for each, longest first. With --check,
exits 1 when a function over the limit is not in the allow-list (--allow,
default scripts/long_functions_allowed.txt: one `path name  # reason` a line);
entries that are no longer long are reported, so the list can be shortened.
Exit 2 on usage errors or an unreadable allow-list.
"""
import argparse
import os
import re
import sys

TOKEN = re.compile(r"""
    (?P<num>\.?\d(?:[eEpP][+-]|[\w.']|)*)
  | (?P<id>[A-Za-z_]\w*)
  | (?P<op>::|->|[{}()\[\];:,<>=~&*])
  | (?P<other>\S)
""", re.VERBOSE)

RAW_STRING = re.compile(r'R"([^()\\ ]{0,16})\(')


def strip_source(text):
    """The text with comments, literals and preprocessor lines blanked.

    Newlines are kept so that line numbers still hold; a literal becomes a
    single token `""` so a declaration such as extern "C" keeps its shape.
    """
    out = []
    i, n = 0, len(text)
    line_start = True
    while i < n:
        c = text[i]
        if line_start and c in " \t":
            out.append(c)
            i += 1
            continue
        if line_start and c == "#":
            # A preprocessor line, with its continuations.
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    out.append("\n")
                    i += 2
                    continue
                i += 1
            continue
        line_start = False
        if c == "\n":
            out.append(c)
            line_start = True
            i += 1
        elif text.startswith("//", i):
            while i < n and text[i] != "\n":
                i += 1
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append("\n" * text.count("\n", i, end) + " ")
            i = end
        elif c == "R" and RAW_STRING.match(text, i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = RAW_STRING.match(text, i)
            close = ")" + m.group(1) + '"'
            end = text.find(close, m.end())
            end = n if end < 0 else end + len(close)
            out.append('""' + "\n" * text.count("\n", i, end))
            i = end
        elif c == '"' or (c == "'" and not (i > 0 and text[i - 1].isalnum())):
            # A string or character literal (a ' after a digit separates digits).
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append('""')
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def tokenize(text):
    tokens = []
    line = 1
    pos = 0
    for m in TOKEN.finditer(text):
        line += text.count("\n", pos, m.start())
        pos = m.start()
        tokens.append((m.group(0), line))
    return tokens


def top_level(header):
    """The header's tokens outside parentheses, brackets and template brackets."""
    depth = 0
    result = []
    for k, (tok, _) in enumerate(header):
        if tok in "([":
            depth += 1
        elif tok in ")]":
            depth -= 1
        elif depth == 0:
            result.append((k, tok))
    return result


def drop_templates(header):
    """The header without its leading `template <...>` clauses."""
    k = 0
    while k < len(header) and header[k][0] == "template":
        k += 1
        depth = 0
        while k < len(header):
            tok = header[k][0]
            k += 1
            if tok == "<":
                depth += 1
            elif tok == ">":
                depth -= 1
                if depth == 0:
                    break
    return header[k:]


def function_name(header):
    """The (qualified) name before the parameter list and its line, or None."""
    for k, (tok, line) in enumerate(header):
        if tok == "operator":
            j = k + 1
            name = "operator"
            if j + 1 < len(header) and header[j][0] == "(" and header[j + 1][0] == ")":
                name, j = "operator()", j + 2
            while j < len(header) and header[j][0] != "(":
                name += header[j][0]
                j += 1
            return qualify(header, k, name), line
        if tok == "(" and k > 0:
            prev = header[k - 1][0]
            if re.match(r"[A-Za-z_~]", prev) and prev not in ("decltype", "alignas", "__attribute__", "noexcept",
                                                                  "sizeof", "requires"):
                return qualify(header, k - 1, prev), header[k - 1][1]
            if prev == ">":
                return None  # a template's arguments: look further on
    return None


def qualify(header, k, name):
    """The name with its Class:: and ~ prefixes."""
    while k >= 1 and header[k - 1][0] == "~":
        name = "~" + name
        k -= 1
    while k >= 2 and header[k - 1][0] == "::":
        name = header[k - 2][0] + "::" + name
        k -= 2
    return name


class Scanner:
    def __init__(self, tokens):
        self.tokens = tokens
        self.i = 0
        self.functions = []  # (line, name, length)

    def skip_block(self):
        """From just past a '{', to just past its matching '}'; the closing line."""
        depth = 1
        while self.i < len(self.tokens):
            tok, line = self.tokens[self.i]
            self.i += 1
            if tok == "{":
                depth += 1
            elif tok == "}":
                depth -= 1
                if depth == 0:
                    return line
        return self.tokens[-1][1] if self.tokens else 0

    def scope(self, class_names=()):
        header = []
        while self.i < len(self.tokens):
            tok, line = self.tokens[self.i]
            self.i += 1
            if tok == ";":
                header = []
            elif tok == "}":
                return
            elif tok == "{":
                header = self.open_brace(header, class_names)
            elif tok in ("public", "private", "protected") and self.i < len(self.tokens) and \
                    self.tokens[self.i][0] == ":" and not header:
                self.i += 1
            else:
                header.append((tok, line))

    def open_brace(self, header, class_names):
        """Classify the brace just read after `header`; the header to go on with."""
        words = [t for t, _ in header]
        body = drop_templates(header)
        first = [t for t, _ in body if t not in ("inline", "export")][:1]
        if first == ["namespace"] or (words[:1] == ["extern"] and words[1:2] == ['""'] and len(words) == 2):
            self.scope()
            return []
        top = top_level(body)
        top_words = [t for _, t in top]
        has_params = any(t == "(" for t, _ in body)
        if first and first[0] in ("class", "struct", "union") and not has_params:
            name = ""
            for t in top_words[1:]:
                if t in (":", "final", "alignas"):
                    break
                name += t
            self.scope(class_names + (name,))
            return [("}", 0)]  # what follows is a declarator such as `} x;`
        if first and first[0] == "enum":
            self.skip_block()
            return [("}", 0)]
        # A constructor's braced member initializer: `) : a_{x}` or `, b_{y}`.
        if has_params and self.in_initializer_list(body):
            self.skip_block()
            return header + [("{}", 0)]
        if has_params and "=" not in top_words[:1]:
            found = function_name(body)
            if found and not self.is_initializer(body):
                name, line = found
                end = self.skip_block()
                if class_names and "::" not in name:
                    name = "::".join(n for n in class_names if n) + "::" + name
                self.functions.append((line, name, end - line + 1))
                return []
        self.skip_block()
        return header + [("{}", 0)]

    @staticmethod
    def is_initializer(body):
        """`T x = f(...) {` cannot be; `T x{...}` has no parameter list before the brace."""
        top = top_level(body)
        params_seen = False
        for k, t in top:
            if t == "=" and not params_seen:
                prev = body[k - 1][0] if k else ""
                if prev != "operator":
                    return True
            if k + 1 < len(body) and body[k + 1][0] == "(":
                params_seen = True
        return False

    @staticmethod
    def in_initializer_list(body):
        """After `) :` at top level, a brace straight after a name (or template) initializes a member."""
        top = top_level(body)
        colon = None
        for idx, (k, t) in enumerate(top):
            if t == ":" and k > 0 and body[k - 1][0] == ")":
                colon = k
                break
        if colon is None:
            return False
        last = body[-1][0]
        return bool(re.match(r"[A-Za-z_]", last)) or last == ">"


def scan_file(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        text = f.read()
    scanner = Scanner(tokenize(strip_source(text)))
    while scanner.i < len(scanner.tokens):
        scanner.scope()  # a stray '}' at file scope ends one scope; go on
    return scanner.functions


def library_files(root):
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames[:] = sorted(d for d in dirnames if d != "tests")
        for name in sorted(filenames):
            if name.endswith((".cpp", ".h", ".hpp")):
                yield os.path.join(dirpath, name)


def read_allow_list(path):
    allowed = {}
    with open(path, encoding="utf-8") as f:
        for number, raw in enumerate(f, 1):
            line = raw.strip()
            if not line or line.startswith("#"):
                continue
            entry, _, reason = line.partition("#")
            fields = entry.split()
            if len(fields) != 2 or not reason.strip():
                raise ValueError(f"{path}:{number}: expected `path name  # reason`, got: {line}")
            allowed[(fields[0], fields[1])] = reason.strip()
    return allowed


def main(argv=None):
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--root", default=os.path.dirname(here), help="repository root (default: this script's parent)")
    parser.add_argument("--max", type=int, default=150, help="longest length allowed, in lines (default 150)")
    parser.add_argument("--check", action="store_true", help="exit 1 on a long function not in the allow-list")
    parser.add_argument("--allow", default=os.path.join(here, "long_functions_allowed.txt"),
                        help="allow-list for --check (default scripts/long_functions_allowed.txt)")
    args = parser.parse_args(argv)

    common = os.path.join(args.root, "common")
    if not os.path.isdir(common):
        print(f"long_functions: error: {common}: no such folder", file=sys.stderr)
        return 2
    found = []
    for path in library_files(common):
        rel = os.path.relpath(path, args.root)
        for line, name, length in scan_file(path):
            if length > args.max:
                found.append((length, rel, line, name))
    found.sort(key=lambda f: (-f[0], f[1], f[2]))

    allowed = {}
    if args.check and os.path.exists(args.allow):
        try:
            allowed = read_allow_list(args.allow)
        except (OSError, ValueError) as e:
            print(f"long_functions: error: {e}", file=sys.stderr)
            return 2
    new = 0
    for length, rel, line, name in found:
        mark = ""
        if args.check:
            mark = "  (allowed: " + allowed[(rel, name)] + ")" if (rel, name) in allowed else "  NEW"
            new += (rel, name) not in allowed
        print(f"{rel}:{line}: {name} ({length} lines){mark}")
    if args.check:
        long_now = {(rel, name) for _, rel, _, name in found}
        for rel, name in sorted(set(allowed) - long_now):
            print(f"long_functions: note: {rel} {name} is in the allow-list but no longer over {args.max} lines; "
                  "remove it")
        if new:
            print(f"long_functions: {new} function(s) over {args.max} lines not in {os.path.relpath(args.allow)}: "
                  "split them into phases (ARCHITECTURE.md, \"Reading one algorithm\")", file=sys.stderr)
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
