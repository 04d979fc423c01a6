"""Reading the shell blocks of a document (README.md, docs/*.md) for the
tests that run them as written."""


def commands(body):
    """The commands of an sh block: continuation lines joined, comment-only
    and blank lines dropped."""
    out, cur = [], ""
    for line in body.splitlines():
        cur += line
        if line.endswith("\\"):
            cur = cur[:-1] + " "
            continue
        if cur.strip() and not cur.lstrip().startswith("#"):
            out.append(cur)
        cur = ""
    return out


def console(body):
    """[(command, [expected output lines])] of a console block."""
    out = []
    for line in body.splitlines():
        if line.startswith("$ "):
            out.append((line[2:], []))
        elif out and line.strip() and line.strip() != "...":
            out[-1][1].append(line.rstrip())
    return out
