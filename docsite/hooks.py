"""MkDocs hooks for the libvbl site (mkdocs.yml: hooks).

- on_config: drops nav entries whose page does not exist (yet), so a slot can wait for a
  generated page (docs/readme/options_table.md) without failing `mkdocs build --strict`.
- on_page_markdown: replaces a line `<!-- vbl-help: ARGS -->` with the output of
  `$VBL_CLI ARGS` (the `vbl` command's own help text) in a code block; without VBL_CLI (a plain
  `mkdocs build`) it says how to get that text instead.
- on_page_markdown: replaces a line `<!-- vbl-file: PATH -->` (PATH relative to the project
  root, e.g. a sample scene) with that file's text in a code block, so examples stay the files
  the tests render.
"""
import os
import re
import subprocess

_HELP = re.compile(r"^<!-- vbl-help: (.*?) -->$", re.M)
_FILE = re.compile(r"^<!-- vbl-file: (.*?) -->$", re.M)
_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _existing(items, docs_dir):
    kept = []
    for item in items:
        if isinstance(item, dict):
            (title, value), = item.items()
            if isinstance(value, list):
                value = _existing(value, docs_dir)
                if value:
                    kept.append({title: value})
            elif value.startswith(("http:", "https:")) or os.path.exists(os.path.join(docs_dir, value)):
                kept.append(item)
        elif os.path.exists(os.path.join(docs_dir, item)):
            kept.append(item)
    return kept


def on_config(config, **kwargs):
    if config.get("nav"):
        config["nav"] = _existing(config["nav"], config["docs_dir"])
    return config


def _help_block(match):
    args = match.group(1).split()
    cli = os.environ.get("VBL_CLI")
    if not cli:
        return "*(Run `vbl %s` for this text; the site build fills it in when `VBL_CLI` names the `vbl` binary.)*" % " ".join(args)
    run = subprocess.run([cli] + args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         universal_newlines=True, check=False)
    text = run.stdout.rstrip("\n")
    if run.returncode != 0:
        raise RuntimeError("vbl %s exited with %d:\n%s" % (" ".join(args), run.returncode, text))
    return "```text\n$ vbl %s\n%s\n```" % (" ".join(args), text)


def _file_block(match):
    path = match.group(1).strip()
    with open(os.path.join(_ROOT, path), encoding="utf-8") as f:
        text = f.read().rstrip("\n")
    language = {".json": "json", ".sh": "sh", ".py": "python", ".c": "c", ".h": "c"}.get(
        os.path.splitext(path)[1], "text")
    return "`%s`:\n\n```%s\n%s\n```" % (path, language, text)


def on_page_markdown(markdown, **kwargs):
    return _FILE.sub(_file_block, _HELP.sub(_help_block, markdown))
