#!/usr/bin/env python3
"""ray(1) and the bash and zsh completions against `ray --help` (cmake/reference.cmake).

Every option that `ray --help`, `ray view --help` and `ray explain --help` list must be
  - in the manual page as man renders it (an entry of its own), and every subcommand that
    `ray --help` lists a section of its own;
  - offered by the bash completion after a dash, for that command (the completion function
    run in bash, as a Tab would), with the values the issue names: --aa's modes, --device's
    devices as `ray --list-devices` gives them, scene files (.xml, .json, .ini) and the
    subcommands for the first argument;
  - in the zsh completion's function for that command (and the script parses, where zsh is).
The comparison is shown to fail first: a manual page and completions with --aa taken out
must be refused, naming it.

Usage: reference_pages.py RAY MANUAL_PAGE BASH_COMPLETION ZSH_COMPLETION
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

ENTRY = re.compile(r"^  (-\S.*?)(?:\s{2,}|$)")
OPTION = re.compile(r"(?<![\w-])(--?[A-Za-z][\w-]*)")


def help_options(ray, subcommand):
    """The options a command's --help lists (its entries' names), in order."""
    text = subprocess.run([ray, *([subcommand] if subcommand else []), "--help"], capture_output=True,
                          text=True, check=True).stdout
    names = []
    for line in text.splitlines():
        match = ENTRY.match(line)
        if match:
            names += [name for name in OPTION.findall(match.group(1)) if name not in names]
    if len(names) < 3:
        raise SystemExit(f"FAIL: `ray {subcommand} --help` lists only {names}: its format changed?")
    return names


def subcommands(ray):
    """The subcommands `ray --help` lists ("  ray view <scene.xml> ...")."""
    text = subprocess.run([ray, "--help"], capture_output=True, text=True, check=True).stdout
    listed = re.findall(r"^  ray (\w+) ", text.split("\nsubcommands:\n", 1)[1], re.M)
    if not listed:
        raise SystemExit("FAIL: `ray --help` lists no subcommands")
    return listed


def rendered_manual(page_text):
    """The manual page as `man` shows it (plain text), from its roff."""
    with tempfile.NamedTemporaryFile("w", suffix=".1", delete=False) as page:
        page.write(page_text)
    try:
        if shutil.which("man"):
            shown = subprocess.run(["man", "-l", page.name], capture_output=True, text=True,
                                   env={**os.environ, "MANWIDTH": "200", "MAN_KEEP_FORMATTING": "0",
                                        "MANPAGER": "cat", "PAGER": "cat"}, check=True).stdout
            return re.sub(r".\x08", "", shown)  # overstrikes (bold) off
        return re.sub(r"\\f[BIRP]|\\-|\\&|\\e", lambda m: {"\\-": "-", "\\e": "\\"}.get(m.group(0), ""), page_text)
    finally:
        os.unlink(page.name)


def manual_problems(page_text, commands, listed_subcommands):
    """What the manual page lacks: an option of a --help without an entry of its own (a line
    that starts with it, as man sets an entry's term), a subcommand without its section."""
    shown = rendered_manual(page_text)
    terms = set()
    for line in shown.splitlines():
        stripped = line.strip()
        if stripped.startswith("-"):
            terms.update(OPTION.findall(re.split(r"\s{2,}", stripped)[0]))
    problems = []
    for subcommand, options in commands.items():
        for option in options:
            if option not in terms:
                problems.append(f"man ray has no entry for {option} (ray {subcommand} --help lists it)".replace("  ", " "))
    for subcommand in listed_subcommands:
        if not re.search(rf"^\s*ray {subcommand}\s*$", shown, re.M):
            problems.append(f"man ray has no section for `ray {subcommand}`")
    return problems


def bash_complete(script, words, folder=None):
    """What the bash completion offers for `words` (the last one being completed), run as
    bash runs it for a Tab."""
    quoted = " ".join("'" + word.replace("'", "'\\''") + "'" for word in words)
    program = (f"source '{script}'\nCOMP_WORDS=({quoted})\nCOMP_CWORD={len(words) - 1}\n"
               "_ray\nprintf '%s\\n' \"${COMPREPLY[@]}\"\n")
    result = subprocess.run(["bash", "-c", program], capture_output=True, text=True, cwd=folder)
    if result.returncode != 0:
        raise SystemExit(f"FAIL: the bash completion failed for {words}: {result.stderr}")
    return [line for line in result.stdout.splitlines() if line]


def bash_problems(script, ray, commands, listed_subcommands, devices):
    problems = []
    for subcommand, options in commands.items():
        words = [ray, *([subcommand] if subcommand else []), "-"]
        offered = set(bash_complete(script, words))
        problems += [f"bash completion does not offer {option} after `ray {subcommand}`".replace("  ", " ")
                     for option in options if option not in offered]
    checks = [([ray, "--aa", ""], {"off", "course", "stratified", "adaptive"}, "--aa's modes"),
              ([ray, "view", "scene.xml", "--device", ""], {"auto", "cpu", "gpu", "all", "ref", *devices},
               "--device's devices"),
              ([ray, "explain", "--texture-filter", ""], {"nearest", "bilinear", "trilinear", "course"},
               "--texture-filter's filters")]
    for words, expected, what in checks:
        offered = set(bash_complete(script, words))
        if not expected <= offered:
            problems.append(f"bash completion of {what} offers {sorted(offered)}, not {sorted(expected)}")
    with tempfile.TemporaryDirectory() as folder:
        for name in ["a.xml", "b.json", "c.ini", "notes.txt"]:
            open(os.path.join(folder, name), "w").close()
        os.mkdir(os.path.join(folder, "scenes"))
        first = set(bash_complete(script, [ray, ""], folder))
        expected = {"a.xml", "b.json", "c.ini", "scenes", *listed_subcommands}
        if first != expected:
            problems.append(f"bash completion of the first argument offers {sorted(first)}, not {sorted(expected)}")
        later = set(bash_complete(script, [ray, "view", ""], folder))
        if later != {"a.xml", "b.json", "c.ini", "scenes"}:
            problems.append(f"bash completion of `ray view`'s scene offers {sorted(later)}")
        output = set(bash_complete(script, [ray, "a.xml", "-o", "n"], folder))
        if output != {"notes.txt"}:
            problems.append(f"bash completion of -o's file offers {sorted(output)}, not notes.txt")
    return problems


def zsh_problems(script_text, commands):
    """Each command's options in its zsh function (_ray_render, _ray_view, ...)."""
    problems = []
    for subcommand, options in commands.items():
        function = re.search(rf"^_ray_{subcommand or 'render'}\(\) \{{\n(.*?)^\}}", script_text, re.M | re.S)
        if not function:
            problems.append(f"the zsh completion has no function for `ray {subcommand}`".replace("  ", " "))
            continue
        specs = set()
        for line in function.group(1).splitlines():
            head = re.match(r"\s*'(?:\(([^)]*)\)'\{([^}]*)\}'|(-[^[']+)\[)", line)
            if head:
                specs.update((head.group(2) or head.group(3) or "").split(","))
        problems += [f"the zsh completion does not offer {option} for `ray {subcommand}`".replace("  ", " ")
                     for option in options if option not in specs]
    return problems


def listed_devices(ray):
    shown = subprocess.run([ray, "--list-devices"], capture_output=True, text=True).stdout
    return re.findall(r"^(\d+): ", shown, re.M)


def main():
    ray, manual, bash_script, zsh_script = (os.path.abspath(path) for path in sys.argv[1:5])
    listed_subcommands = subcommands(ray)
    commands = {"": help_options(ray, "")}
    for subcommand in listed_subcommands:
        commands[subcommand] = help_options(ray, subcommand)
    page_text = open(manual, encoding="utf-8").read()
    zsh_text = open(zsh_script, encoding="utf-8").read()
    devices = listed_devices(ray)

    # The comparison can fail: without --aa's entry and words, each check must name it.
    cut_page = re.sub(r"^\.TP\n\\fB\\-\\-aa\\fR.*?\n.*?\n", "", page_text, flags=re.M)
    with tempfile.TemporaryDirectory() as folder:
        cut_bash = os.path.join(folder, "ray")
        with open(cut_bash, "w") as out:
            out.write(open(bash_script).read().replace(" --aa ", " "))
        cut_zsh = zsh_text.replace("'--aa[", "'--aaa[")
        for what, problems in [("man", manual_problems(cut_page, commands, listed_subcommands)),
                               ("bash", bash_problems(cut_bash, ray, commands, listed_subcommands, devices)),
                               ("zsh", zsh_problems(cut_zsh, commands))]:
            if not any("--aa " in problem or problem.endswith("--aa") or "offer --aa" in problem for problem in problems):
                raise SystemExit(f"FAIL: the {what} check passes a copy without --aa: {problems}")
    print("self-test: each check refuses a manual page or completion without --aa")

    problems = manual_problems(page_text, commands, listed_subcommands)
    problems += bash_problems(bash_script, ray, commands, listed_subcommands, devices)
    problems += zsh_problems(zsh_text, commands)
    if shutil.which("zsh"):
        result = subprocess.run(["zsh", "-n", zsh_script], capture_output=True, text=True)
        if result.returncode != 0:
            problems.append("zsh -n refuses the zsh completion: " + result.stderr)
    result = subprocess.run(["bash", "-n", bash_script], capture_output=True, text=True)
    if result.returncode != 0:
        problems.append("bash -n refuses the bash completion: " + result.stderr)
    for problem in problems:
        print("FAIL:", problem)
    if problems:
        return 1
    counted = sum(len(options) for options in commands.values())
    print(f"reference_pages: all passed ({counted} options of {len(commands)} commands in man ray, bash and zsh; "
          f"devices {devices or 'none'})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
