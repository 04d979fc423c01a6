#!/usr/bin/env python3
"""Write python/igea/_capi.py, the Python mirror of the C API, from the
public headers include/igea/*.h.

    gen_capi.py [OUT]        (default: python/igea/_capi.py beside this script)
    gen_capi.py --check      exit 1 if OUT differs from a fresh generation

The mirror holds every #define IGEA_X constant of the headers as X (the
version included), and PROTOTYPES: for every IGEA_API function its ctypes
return type and its (argument name, ctypes type) pairs in header order;
INPUTS: for every function, the pointer arguments it only reads (const).
Standard library only; an unknown C type or a macro whose value cannot be
computed stops the generation with a message naming it.
"""
import ast
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
INCLUDE = os.path.join(ROOT, "include", "igea")
OUT = os.path.join(HERE, "igea", "_capi.py")

# C type (spaces removed, const dropped) -> ctypes spelling
_CTYPES = {"void": "None", "int": "c_int", "double": "c_double", "int*": "_PI",
           "double*": "_PD", "char*": "c_char_p"}
_HANDLE = re.compile(r"igea_\w+\*$")          # a handle: struct igea_x *
_HANDLE_OUT = re.compile(r"igea_\w+\*\*$")    # where a new handle is stored


def ctype(c, where):
    t = re.sub(r"\bconst\b", "", c).replace(" ", "")
    if t in _CTYPES:
        return _CTYPES[t]
    if _HANDLE.match(t):
        return "c_void_p"
    if _HANDLE_OUT.match(t):
        return "_PH"
    raise SystemExit("gen_capi: %s: unsupported C type %r" % (where, c))


def _strip_comments(text):
    """Comments removed, line breaks kept."""
    return re.sub(r"/\*.*?\*/|//[^\n]*", lambda m: "\n" * m.group(0).count("\n"), text,
                  flags=re.S)


def parse(include=INCLUDE):
    """([(header, macro, body)], [(header, restype, name, [(ctype, argname)])])
    in header order (headers sorted by name)."""
    macros, funcs = [], []
    for fn in sorted(os.listdir(include)):
        if not fn.endswith(".h"):
            continue
        text = _strip_comments(open(os.path.join(include, fn)).read())
        text = text.replace("\\\n", " ")
        for m in re.finditer(r"(?m)^[ \t]*#[ \t]*define[ \t]+(IGEA_\w+)(\(?)[ \t]*(.*)$", text):
            name, fnlike, body = m.group(1), m.group(2), m.group(3).strip()
            if fnlike or not body or name == "IGEA_API":
                continue  # function-like helpers, include guards, the export macro
            macros.append((fn, name, body))
        for m in re.finditer(r"IGEA_API\s+([^;{}#]*?)\b(igea_\w+)\s*\(([^)]*)\)\s*;", text):
            ret, name, plist = " ".join(m.group(1).split()), m.group(2), " ".join(m.group(3).split())
            params = []
            if plist != "void":
                for p in plist.split(","):
                    pm = re.match(r"\s*(.*?)\s*\b(\w+)\s*$", p)
                    if not pm or not pm.group(1):
                        raise SystemExit("gen_capi: %s: %s: a parameter without a name: %r"
                                         % (fn, name, p))
                    params.append((pm.group(1), pm.group(2)))
            funcs.append((fn, ret, name, params))
    return macros, funcs


_OPS = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Constant, ast.Add, ast.Sub, ast.Mult,
        ast.USub, ast.UAdd, ast.Name, ast.Load)


def evaluate(macros):
    """{macro: Python value}: numbers, string literals and integer
    arithmetic of earlier macros. IGEA_VERSION_STRING, built in C by
    stringizing the three numbers, is "MAJOR.MINOR.PATCH"."""
    values = {}
    for fn, name, body in macros:
        if name == "IGEA_VERSION_STRING":
            v = "%d.%d.%d" % tuple(values["IGEA_VERSION_" + k] for k in ("MAJOR", "MINOR", "PATCH"))
            if body.startswith('"') and ast.literal_eval(body) != v:
                raise SystemExit("gen_capi: %s: %s %s is not the version numbers %s"
                                 % (fn, name, body, v))
            values[name] = v
            continue
        if re.fullmatch(r'"(?:[^"\\]|\\.)*"(?:\s*"(?:[^"\\]|\\.)*")*', body):
            values[name] = ast.literal_eval(body.replace('" "', "").replace('""', ""))
            continue
        expr = re.sub(r"(?<=\d)[uUlL]+\b", "", body)
        try:
            tree = ast.parse(expr, mode="eval")
            if not all(isinstance(n, _OPS) for n in ast.walk(tree)):
                raise ValueError(body)
            v = eval(compile(tree, fn, "eval"), {"__builtins__": {}}, dict(values))
        except (SyntaxError, ValueError, NameError, TypeError) as exc:
            raise SystemExit("gen_capi: %s: cannot compute %s = %s (%s)" % (fn, name, body, exc))
        values[name] = v
    return values


def _wrap(head, items, tail, indent, width=99):
    """head item item ... tail, broken into lines of at most width."""
    lines, line = [], head
    for it in items + [tail]:
        sep = "" if it is tail or line.endswith("(") or line == " " * indent else " "
        if len(line) + len(sep) + len(it) > width:
            lines.append(line)
            line, sep = " " * indent, ""
        line += sep + it
    return "\n".join(lines + [line]) + "\n"


def generate(include=INCLUDE):
    macros, funcs = parse(include)
    values = evaluate(macros)
    out = ['"""The C API of libigea: generated by python/gen_capi.py from include/igea/*.h.\n'
           "\n"
           "Do not edit: run 'make' (or python/gen_capi.py) after changing a header.\n"
           "Every #define IGEA_X of the headers is X here; PROTOTYPES maps each\n"
           "IGEA_API function to (ctypes return type, ((argument name, ctypes type), ...)).\n"
           '"""\n',
           "from ctypes import POINTER, c_char_p, c_double, c_int, c_void_p\n\n"
           "_PD, _PI, _PH = POINTER(c_double), POINTER(c_int), POINTER(c_void_p)\n"]
    header = None
    for fn, name, _ in macros:
        if fn != header:
            header = fn
            out.append("\n# igea/%s\n" % fn)
        v = values[name]
        out.append(('%s = "%s"\n' if isinstance(v, str) else "%s = %r\n") % (name[len("IGEA_"):], v))
    out.append("\nPROTOTYPES = {\n")
    header = None
    for fn, ret, name, params in funcs:
        if fn != header:
            header = fn
            out.append("    # igea/%s\n" % fn)
        where = "%s: %s" % (fn, name)
        items = ['("%s", %s),' % (pn, ctype(pt, where)) for pt, pn in params]
        out.append(_wrap('    "%s": (%s, (' % (name, ctype(ret, where)), items, ")),", 8))
    out.append("}\n")
    out.append("\n# The pointer arguments each function only reads (const in the header),\n"
               "# in order: where a data error (NaN, a sigma <= 0) may come from.\n"
               "INPUTS = {\n")
    for fn, ret, name, params in funcs:
        ins = ['"%s",' % pn for pt, pn in params
               if re.search(r"\bconst\b", pt) and "*" in pt and not _HANDLE.match(
                   re.sub(r"\bconst\b", "", pt).replace(" ", ""))]
        if ins:
            out.append(_wrap('    "%s": (' % name, ins, "),", 8))
    out.append("}\n")
    return "".join(out)


def main(argv):
    check = "--check" in argv
    rest = [a for a in argv if a != "--check"]
    path = rest[0] if rest else OUT
    text = generate()
    if check:
        old = open(path).read() if os.path.exists(path) else ""
        if old != text:
            sys.stderr.write("gen_capi: %s differs from the headers: run python/gen_capi.py\n"
                             % path)
            return 1
        return 0
    old = open(path).read() if os.path.exists(path) else None
    if old == text:
        os.utime(path)  # up to date with the headers, for make
    else:
        tmp = path + ".tmp%d" % os.getpid()
        with open(tmp, "w") as f:
            f.write(text)
        os.replace(tmp, path)  # atomic: a concurrent reader sees the old or the new file
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
