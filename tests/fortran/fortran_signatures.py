#!/usr/bin/python3
"""Every bind(C) interface in src/fortran/*.f90 matches its C prototype in
include/vibroimpact/*.h: the same number of arguments, each of the matching
interoperable type and passed the same way (by value or by reference), and
the same result.  Run by tests/fortran_symbols_test.sh; prints one line per
mismatch and exits 1 if there is any.

    fortran_signatures.py SRC
"""
import glob
import os
import re
import sys

OPAQUE = set()  # handles: typedef struct vi_x vi_x; (filled from the headers)


def c_kind(decl, result=False):
    """Canonical kind of a C parameter (or result) declaration."""
    d = re.sub(r"\bconst\b", "", decl).strip()
    d = re.sub(r"\s+", " ", d)
    if result:
        if "*" in d:
            return "ptr"
        return {"void": "sub", "double": "double", "int": "int",
                "int64_t": "int64", "long": "long"}.get(d, "?" + d)
    if d == "void":
        return None
    d = re.sub(r"\s*\b\w+$", "", d) if not d.endswith("*") else d  # drop the name
    d = re.sub(r"\s*\[\s*\]$", " *", d)
    stars = d.count("*")
    base = d.replace("*", "").strip()
    if base == "void" and stars == 0:
        return None
    if stars >= 2:
        return "ptr:ref"
    if re.fullmatch(r"vi_\w+_fn", base):
        return "funptr:value"
    if stars == 1:
        if base in OPAQUE:
            return "ptr:value"
        if re.fullmatch(r"vi_\w+", base):  # a struct: type(vi_x) by reference
            return base + ":ref"
        if base == "void":
            return "ptr:value"
        return {"double": "double", "int": "int", "char": "char",
                "int64_t": "int64"}.get(base, "?" + base) + ":ref"
    return {"double": "double", "int": "int", "int64_t": "int64",
            "long": "long"}.get(base, "?" + base) + ":value"


def c_prototypes(src):
    text = ""
    for h in sorted(glob.glob(os.path.join(src, "include/vibroimpact/*.h*"))):
        text += open(h).read() + "\n"
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    OPAQUE.update(m.group(1) for m in re.finditer(r"typedef\s+struct\s+(\w+)\s+\1\s*;", text))
    protos = {}
    for m in re.finditer(r"VI_API\s+([^;{}()]*?)\b(vi_\w+)\s*\(([^;]*?)\)\s*;", text, re.S):
        ret, name, args = m.group(1), m.group(2), m.group(3)
        # split the parameters at top-level commas (none nest here)
        params = [p.strip() for p in args.split(",") if p.strip()]
        kinds = [k for k in (c_kind(p) for p in params) if k is not None]
        protos[name] = (c_kind(ret, result=True), kinds)
    return protos


F_BASE = [(r"type\(c_ptr\)", "ptr"), (r"type\(c_funptr\)", "funptr"),
          (r"real\(c_double\)", "double"), (r"integer\(c_int\)", "int"),
          (r"integer\(c_int64_t\)", "int64"), (r"integer\(c_long\)", "long"),
          (r"character\(kind=c_char\)", "char")]


def f_base(spec):
    for pat, kind in F_BASE:
        if re.match(pat + r"\s*$", spec.strip(), re.I):
            return kind
    m = re.match(r"type\((vi_\w+)\)\s*$", spec.strip(), re.I)
    return m.group(1).lower() if m else "?" + spec.strip()


def split_top(s):
    out, depth, cur = [], 0, ""
    for ch in s:
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
        if ch == "," and depth == 0:
            out.append(cur)
            cur = ""
        else:
            cur += ch
    if cur.strip():
        out.append(cur)
    return [x.strip() for x in out]


def fortran_interfaces(src):
    ifaces = {}
    for path in sorted(glob.glob(os.path.join(src, "src/fortran/*.f90"))):
        lines, buf = [], ""
        for raw in open(path):
            line = raw.split("!", 1)[0].rstrip()
            if line.endswith("&"):
                buf += line[:-1] + " "
                continue
            lines.append(buf + line)
            buf = ""
        cur = None
        for line in lines:
            m = re.match(r"\s*(.*?)\b(function|subroutine)\s+(\w+)\s*\(([^)]*)\)\s*bind\(C,\s*name\s*=\s*\"(\w+)\"\)",
                         line, re.I)
            if m:
                ret = "sub" if m.group(2).lower() == "subroutine" else f_base(m.group(1))
                args = [a.strip().lower() for a in m.group(4).split(",") if a.strip()]
                cur = {"cname": m.group(5), "ret": ret, "args": args, "decl": {}}
                continue
            if cur is None:
                continue
            if re.match(r"\s*end\s+(function|subroutine)", line, re.I):
                ifaces[cur["cname"]] = (cur["ret"], [cur["decl"].get(a, "?undeclared " + a)
                                                     for a in cur["args"]])
                cur = None
                continue
            if "::" in line:
                spec, names = line.split("::", 1)
                parts = split_top(spec)
                base = f_base(parts[0])
                by = "value" if any(p.lower() == "value" for p in parts[1:]) else "ref"
                for nm in split_top(names):
                    nm = re.sub(r"\(.*", "", nm).strip().lower()
                    cur["decl"][nm] = base + ":" + by
    return ifaces


def main():
    src = sys.argv[1]
    c, f = c_prototypes(src), fortran_interfaces(src)
    bad = 0
    for name in sorted(f):
        if name not in c:
            continue  # no prototype (strlen, or not exported): the nm check's business
        cret, cargs = c[name]
        fret, fargs = f[name]
        why = []
        if cret != fret:
            why.append(f"result C {cret}, Fortran {fret}")
        if len(cargs) != len(fargs):
            why.append(f"{len(cargs)} C arguments, {len(fargs)} Fortran")
        else:
            for i, (a, b) in enumerate(zip(cargs, fargs)):
                if a != b:
                    why.append(f"argument {i + 1}: C {a}, Fortran {b}")
        if why:
            bad += 1
            print(f"FAIL: {name}: " + "; ".join(why))
    checked = len([n for n in f if n in c])
    print(f"signatures: {checked} Fortran interfaces checked against the C prototypes, "
          f"{bad} mismatched")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
