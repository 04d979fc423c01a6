"""Reading the shell blocks of a document (README.md, docs/*.md) for the
tests that run them as written."""
import re
import subprocess


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


def run_script(commands, cwd, env, where, subshell=False):
    """Run the commands in one bash in cwd; [(status, output)] of each. Each
    must exit 0, or 1 when it is an igea verdict ("rejected"). subshell:
    each command in ( ) so that a cd does not carry over."""
    mark = "@@@doc-block-status"
    form = "(%s)\necho \"%s $?\"\n" if subshell else "%s\necho \"%s $?\"\n"
    script = "exec 2>&1\n" + "".join(form % (c, mark) for c in commands)
    r = subprocess.run(["bash", "-c", script], cwd=str(cwd), env=env, capture_output=True,
                       text=True, timeout=300)
    parts = re.split(r"^%s (\d+)\n" % mark, r.stdout, flags=re.M)
    results = [(int(parts[i + 1]), parts[i]) for i in range(0, len(parts) - 1, 2)]
    assert len(results) == len(commands), "%s: the script stopped early:\n%s" % (where, r.stdout)
    for cmd, (status, output) in zip(commands, results):
        verdict = status == 1 and re.search(r"(^|[\s;&|(])igea\s", cmd)
        assert status == 0 or verdict, "%s: '%s' exited %d:\n%s" % (where, cmd, status, output)
    return results
