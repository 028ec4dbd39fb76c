"""Markdown formatting shared by the sections' report text."""
import math


def fmt_ratio(x):
    if x is None or not isinstance(x, (int, float)) or math.isnan(x) or math.isinf(x):
        return "n/a"
    return "%.2f" % x


def ratio(a, b):
    """a / b, or nan when either is missing or b is 0."""
    if not isinstance(a, (int, float)) or not isinstance(b, (int, float)) or not b:
        return float("nan")
    return a / b


def ms(seconds):
    return "%.0f" % (seconds * 1e3) if isinstance(seconds, (int, float)) else ""


def md_table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


def geomean(v):
    v = [x for x in v if isinstance(x, (int, float)) and x > 0 and not math.isnan(x)]
    return math.exp(sum(math.log(x) for x in v) / len(v)) if v else float("nan")


def commands_block(ctx, *sections):
    """The commands that produced a section's numbers, folded (GitHub renders <details>)."""
    cmds = [c for s in sections for c in (ctx.prov.get(s, {}).get("commands") or ctx.runner.by_section.get(s, []))]
    if not cmds:
        return ""
    return ("\n<details><summary>Commands (%d)</summary>\n\n```sh\n%s\n```\n</details>\n" %
            (len(cmds), "\n".join(cmds)))
