"""Write ``vocabulary.txt`` (the keywords :mod:`~gridlib.io.grdecl.vocabulary` knows) from the
keyword definitions of OPM opm-common (``src/opm/input/eclipse/share/keywords/**``, JSON files).

Run from a checkout (or a bare clone: ``--ref``) of opm-common::

    python -m gridlib.io.grdecl.make_vocabulary /path/to/opm-common --ref release/2022.10/final

Only facts about the ECLIPSE format are taken: each keyword's deck names, sections and the shape
of its data (how many records, and how its end is found), in the terms of opm-common's
``ParserKeyword::initSize``: an explicit ``size`` (a number, ``UNKNOWN``, or an item of another
keyword), ``num_tables`` (tables each ended by an empty record), ``records_set`` (ended by two
empty records), ``code`` (raw text up to an end marker), ``data`` (one record of values), and
otherwise ``items``/``records`` (records ended by an empty record) or no data at all.
"""

from __future__ import annotations

import argparse
import json
import subprocess
from pathlib import Path

KEYWORD_DIR = "src/opm/input/eclipse/share/keywords"
SECTION_LETTERS = {
    "RUNSPEC": "R",
    "GRID": "G",
    "EDIT": "E",
    "PROPS": "P",
    "REGIONS": "N",
    "SOLUTION": "S",
    "SUMMARY": "U",
    "SCHEDULE": "H",
    "SPECIAL": "X",
    "SRUNSPEC": "X",
}
HEADER = """\
# The ECLIPSE / OPM Flow keywords gridlib's deck reader knows: deck name, shape of the data, sections.
# Derived by gridlib/io/grdecl/make_vocabulary.py from OPM opm-common {ref}
# (src/opm/input/eclipse/share/keywords/**, GPL-3): the names, sections and sizes are facts about
# the ECLIPSE format; no code is taken. Keywords only of the SUMMARY section are left out (the
# reader stops there), as are the deck-name patterns of SUMMARY and SCHEDULE keywords.
# A name starting with '~' is a regular expression (Python re, whole name).
# Shapes:  none                 no data (the keyword alone)
#          data                 one record of values (an array)
#          records:N[:MIN]      N records (MIN: a keyword on the next line may end it after MIN)
#          list                 records up to an empty record ('/' alone)
#          sized:KW:I:D:S:F     (item I of keyword KW's first record, default D, plus S) times F records
#          tables:KW:I:D        that many tables, each ended by an empty record
#          open                 records up to the next line that starts with a keyword
#          sets                 records up to two empty records in a row
#          code:END             raw text up to the word END
# Sections: R RUNSPEC, G GRID, E EDIT, P PROPS, N REGIONS, S SOLUTION, U SUMMARY, H SCHEDULE,
#           X SPECIAL.
"""


def _item_position(definitions: dict, keyword: str, item: str) -> tuple[int, str]:
    """1-based position of ``item`` in the first record of ``keyword`` and its default ('-': none;
    position 0: the keyword has no such item)."""
    spec = definitions[keyword]
    items = spec.get("items") or spec.get("records", [[]])[0]
    for position, entry in enumerate(items, start=1):
        if entry["name"] == item:
            default = entry.get("default")
            return position, "-" if default is None else str(int(default))
    return 0, "-"  # a definition naming an item its size keyword lacks (DISPERSE): not sizeable


def shape(spec: dict, definitions: dict) -> str:
    """The shape code of one keyword (see HEADER), following opm-common's ParserKeyword::initSize."""
    size = spec.get("size")
    if size is not None:
        if isinstance(size, int):
            shape_code = "none" if size == 0 else f"records:{size}"
            if "min_size" in spec and size:
                shape_code += f":{spec['min_size']}"
            return shape_code
        if isinstance(size, str):
            return {"UNKNOWN": "open", "SLASH_TERMINATED": "list"}[size]
        position, default = _item_position(definitions, size["keyword"], size["item"])
        factor = len(spec.get("alternating_records", [None]))  # a record of each kind per table
        return f"sized:{size['keyword']}:{position}:{default}:{size.get('shift', 0)}:{factor}"
    if "num_tables" in spec:
        tables = spec["num_tables"]
        position, default = _item_position(definitions, tables["keyword"], tables["item"])
        return f"tables:{tables['keyword']}:{position}:{default}"
    if "records_set" in spec:
        return "sets"
    if "code" in spec:
        return f"code:{spec['code']['end']}"
    if "data" in spec:
        return "data"
    if "items" in spec or "records" in spec:
        return "list"
    return "none"


def _load(source: Path, ref: str | None) -> dict[str, dict]:
    """Every keyword definition by internal name (a later file replaces an earlier, as in opm-common)."""
    texts: dict[str, str] = {}
    if ref is None:
        for path in sorted((source / KEYWORD_DIR).rglob("*")):
            if path.is_file() and path.suffix != ".cmake":
                texts[str(path.relative_to(source))] = path.read_text()
    else:
        git = ["git", f"--git-dir={source}"]
        listing = [*git, "ls-tree", "-r", "--name-only", ref, KEYWORD_DIR]
        names = subprocess.run(listing, check=True, capture_output=True, text=True).stdout.split()
        for name in sorted(n for n in names if not n.endswith(".cmake")):
            texts[name] = subprocess.run(
                [*git, "show", f"{ref}:{name}"], check=True, capture_output=True, text=True
            ).stdout
    definitions = {}
    for name, text in texts.items():
        if not text.strip():  # an empty definition file: no keyword
            continue
        try:
            spec = json.loads(text, strict=False)
        except json.JSONDecodeError:
            spec = _lenient_json(text, name)
        definitions[spec["name"]] = spec
    return definitions


def _lenient_json(text: str, name: str) -> dict:
    """A few definitions are not strict JSON (comments, missing commas); their name, sections
    and size are read from the leading keys."""
    import re

    found = re.search(r'"name"\s*:\s*"([^"]+)"', text)
    sections = re.search(r'"sections"\s*:\s*\[([^\]]*)\]', text)
    size = re.search(r'"size"\s*:\s*(\d+)', text)
    if not (found and sections):
        raise ValueError(f"{name}: cannot read the keyword definition")
    spec: dict = {"name": found.group(1), "sections": re.findall(r'"([A-Z]+)"', sections.group(1))}
    if size:
        spec["size"] = int(size.group(1))
    else:
        spec["items"] = []
    return spec


def vocabulary_lines(definitions: dict[str, dict]) -> list[str]:
    lines = {}
    for spec in definitions.values():
        sections = spec["sections"]
        letters = "".join(sorted({SECTION_LETTERS[s] for s in sections}, key="RGEPNSUHX".index))
        if set(letters) <= {"U"}:
            continue
        code = shape(spec, definitions)
        names = spec.get("deck_names")
        if names is None and "deck_name_regex" not in spec:
            names = [spec["name"]]
        for name in names or []:
            lines[name] = f"{name} {code} {letters}"
        regex = spec.get("deck_name_regex")
        if regex and not set(letters) <= {"U", "H"}:
            lines["~" + regex] = f"~{regex} {code} {letters}"
    return [lines[k] for k in sorted(lines)]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("opm_common", type=Path, help="opm-common checkout, or its git directory with --ref")
    parser.add_argument("--ref", help="a git ref of a bare clone, e.g. release/2022.10/final")
    parser.add_argument("--output", type=Path, default=Path(__file__).with_name("vocabulary.txt"))
    args = parser.parse_args(argv)
    definitions = _load(args.opm_common, args.ref)
    text = HEADER.format(ref=args.ref or "(checkout)") + "\n".join(vocabulary_lines(definitions)) + "\n"
    args.output.write_text(text)


if __name__ == "__main__":
    main()
