#!/usr/bin/env python3
"""Rewrites the kernel launches of a .cu file for the host emulation.

    launches.py IN.cu OUT.cc

Every `Kernel<<<grid, block>>>(args)` becomes
`es::emulation::Launch(dim3(grid), dim3(block), [&] { Kernel(args); })`
(emulation.h); nothing else changes.
"""
import os
import re
import sys


def top_level_comma(text):
    depth = 0
    for i, ch in enumerate(text):
        if ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        elif ch == "," and depth == 0:
            return i
    raise ValueError("no grid, block pair in <<<%s>>>" % text)


def closing_paren(text, open_at):
    depth = 0
    for i in range(open_at, len(text)):
        if text[i] == "(":
            depth += 1
        elif text[i] == ")":
            depth -= 1
            if depth == 0:
                return i
    raise ValueError("unbalanced launch arguments")


def rewrite(src):
    out, at = [], 0
    while True:
        launch = src.find("<<<", at)
        if launch < 0:
            return "".join(out) + src[at:]
        name = re.search(r"(\w+)\s*$", src[at:launch])
        out.append(src[at:at + name.start(1)])
        config_end = src.find(">>>", launch)
        config = src[launch + 3:config_end]
        comma = top_level_comma(config)
        args_open = src.find("(", config_end)
        args_close = closing_paren(src, args_open)
        out.append("es::emulation::Launch(dim3(%s), dim3(%s), [&] { %s(%s); })"
                   % (config[:comma].strip(), config[comma + 1:].strip(),
                      name.group(1), src[args_open + 1:args_close]))
        at = args_close + 1


if __name__ == "__main__":
    with open(sys.argv[1]) as f:
        text = rewrite(f.read())
    os.makedirs(os.path.dirname(os.path.abspath(sys.argv[2])), exist_ok=True)
    with open(sys.argv[2], "w") as f:
        f.write('#line 1 "%s"\n' % sys.argv[1] + text)
