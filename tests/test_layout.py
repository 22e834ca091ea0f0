"""linkage.py reads as its design: numbered sections in the order a reader needs them, each header
saying which earlier sections it uses (and saying it truly), none reaching into a later one or
into another's private names, and nothing imported from tests/ (the program stands without its
tests; tests/test_bench.py runs its benchmarks so)."""

from __future__ import annotations

import ast
import builtins
import re
import subprocess
import sys
from pathlib import Path

import pytest

import linkage
from support.peers import need

SOURCE = Path(linkage.__file__).read_text(encoding="utf-8")
LINES = SOURCE.splitlines()
BANNER = re.compile(r"# ---- (\d+)\. (.+?) -+$")
TREE = ast.parse(SOURCE)


def sections(lines=LINES) -> list[tuple[int, int, str]]:
    """(number, first line, title) of each section banner, in file order."""
    return [(int(m[1]), i + 1, m[2]) for i, line in enumerate(lines) if (m := BANNER.match(line))]


def section_of(lineno: int, banners) -> int:
    """The section a line is in, among `banners` (sections()); 0: the preamble before them."""
    return max((n for n, first, _ in banners if first <= lineno), default=0)


def bindings(tree=TREE) -> list[tuple[str, int]]:
    """Each name the module binds at its top level (def, class, assignment), with the line."""
    bound = []
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names = [node.name]
        elif isinstance(node, (ast.Assign, ast.AnnAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            names = [n.id for t in targets for n in ast.walk(t) if isinstance(n, ast.Name)]
        else:
            continue
        bound += [(name, node.lineno) for name in names]
    return bound


def top_level_names(lines=LINES, tree=TREE) -> dict[str, int]:
    """Each module-level name and the section that defines it."""
    defined, banners = {}, sections(lines)
    for name, lineno in bindings(tree):
        defined.setdefault(name, section_of(lineno, banners))
    return defined


def local_names(node) -> set[str]:
    """Names a function or class binds itself (arguments, assignments, loops, imports)."""
    local = set()
    for n in ast.walk(node):
        if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store):
            local.add(n.id)
        elif isinstance(n, ast.arg):
            local.add(n.arg)
        elif isinstance(n, (ast.Import, ast.ImportFrom)):
            local.update((a.asname or a.name).split(".")[0] for a in n.names)
    return local


def uses(lines=LINES, tree=TREE) -> dict[int, dict[int, set[str]]]:
    """{section: {earlier or later section: the names it takes from there}}."""
    defined, found, banners = top_level_names(lines, tree), {}, sections(lines)
    for node in tree.body:
        here = section_of(node.lineno, banners)
        own = local_names(node) if isinstance(node, (ast.FunctionDef, ast.ClassDef)) else set()
        for n in ast.walk(node):
            if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load) and n.id not in own:
                there = defined.get(n.id)
                if there not in (None, 0, here):
                    found.setdefault(here, {}).setdefault(there, set()).add(n.id)
    return found


def declared_uses() -> dict[int, set[int]]:
    """What each header says: a line "# Uses: sections 1 and 3 (why)." or "# Uses: none." among
    the comment lines right under the banner (the numbers before any parenthesis count)."""
    declared = {}
    for number, first, title in sections():
        header = []
        for line in LINES[first:]:
            if not line.startswith("#"):
                break
            header.append(line)
        said = [line for line in header if line.startswith("# Uses:")]
        assert len(said) == 1, f"section {number} ({title}) has no '# Uses:' line in its header"
        listed = re.split(r"[(;]", said[0])[0]
        declared[number] = {int(n) for n in re.findall(r"\b(\d+)\b", listed)}
    return declared


def test_sections_are_numbered_in_order():
    numbers = [n for n, _, _ in sections()]
    assert numbers == list(range(1, len(numbers) + 1)), numbers
    assert len(numbers) >= 8


def test_no_section_reaches_into_a_later_one():
    later = {(here, there): sorted(names) for here, used in uses().items()
             for there, names in used.items() if there > here}
    assert later == {}, later


def test_each_section_is_one_room():
    """A name with a leading underscore is its section's own: no other section uses it (what
    sections share is named without one)."""
    private = {(here, there): sorted(n for n in names if n.startswith("_"))
               for here, used in uses().items() for there, names in used.items()}
    assert {k: v for k, v in private.items() if v} == {}


def test_each_header_says_which_sections_it_uses():
    used = uses()           # once: in the comprehension it was walked for each section (7 s)
    actual = {n: set(used.get(n, {})) for n, _, _ in sections()}
    assert declared_uses() == actual


def test_the_program_imports_nothing_of_tests():
    tests = {p.stem for p in (Path(linkage.__file__).parent / "tests").glob("**/*.py")}
    tests.add("support")
    imported = set()
    for n in ast.walk(TREE):
        if isinstance(n, ast.Import):
            imported.update(a.name.split(".")[0] for a in n.names)
        elif isinstance(n, ast.ImportFrom) and n.module:
            imported.add(n.module.split(".")[0])
    assert imported & tests == set()
    assert "sys.path" not in SOURCE


def test_the_layout_test_can_fail():
    """A function put into section 1 that calls main() is seen reaching forward, into the last."""
    first = sections()[0][1]
    lines = LINES[:first] + ["def _reach():", "    return main()"] + LINES[first:]
    reached = uses(lines, ast.parse("\n".join(lines)))
    assert reached[1][len(sections())] == {"main"}


def test_the_readmes_layout_matches_the_file():
    """README's "Layout": a row for each section (its line count within 15 %) and each file of
    tests/ and tests/support/, by its path."""
    readme = (Path(linkage.__file__).parent / "README.md").read_text(encoding="utf-8")
    layout = readme[readme.index("\n## Layout\n"):].split("\n## ", 2)[1]
    banners = sections()
    ends = [first for _, first, _ in banners[1:]] + [len(LINES) + 1]
    for (number, first, title), end in zip(banners, ends):
        row = re.search(rf"^\| {number}\. ([^|]+) \| ([\d,]+) \|", layout, re.M)
        assert row and title.startswith(row[1].strip()), (number, title)
        assert abs(int(row[2].replace(",", "")) - (end - first)) <= 0.15 * (end - first), \
            (title, row[2], end - first)
    root = Path(linkage.__file__).parent
    files = [*(root / "tests").glob("*.py"), *(root / "tests" / "support").glob("*.py")]
    assert len(files) > 40
    for path in files:
        assert f"`{path.relative_to(root)}`" in layout, path


def _section_numbers(*titles: str) -> list[int]:
    return [n for n, _, title in sections() if title.startswith(titles)]


def test_the_files_and_messages_use_nothing_and_the_modern_program_never_the_original():
    """Section 1 (files, messages, the terminal) is at the bottom; the engine and all that is
    built on it (what it derives, the numpy path, the linkage, its files, the mechanism view,
    synthesis) never use the 1980s program's sections (they use section 1 for their I/O)."""
    used = uses()
    (files,) = _section_numbers("Files, messages")
    original = _section_numbers("GW-BASIC", "The listing's computation", "The original program")
    assert files == 1 and used.get(files, {}) == {} and len(original) == 3
    modern = _section_numbers("The accurate engine", "What the engine derives", "The numpy path",
                              "The linkage", "DAT and CSV", "The mechanism", "Synthesis")
    assert len(modern) == 13          # the numpy path in three rooms: sweeps, the recipe, forces
    for number in modern:
        assert not set(original) & set(used.get(number, {})), (number, used[number])


SIZE = 850          # lines: "about 800", a room a newcomer can hold
LARGER: dict[str, str] = {}     # a section over SIZE: its title, and the reason it is one room


def section_sizes(lines=LINES) -> dict[str, int]:
    banners = sections(lines)
    ends = [first for _, first, _ in banners[1:]] + [len(lines) + 1]
    return {title: end - first for (_, first, title), end in zip(banners, ends)}


def test_each_section_is_a_room_one_can_hold():
    """No section over about 800 lines but those LARGER names, each with its reason."""
    larger = {title: n for title, n in section_sizes().items() if n > SIZE}
    assert set(larger) == set(LARGER), larger


def offered(lines=LINES) -> dict[int, list[str]]:
    """What each header says it offers: "# Offers: a, b, c." and its continuation lines
    ("#   d, e."), or "# Offers: nothing."."""
    found = {}
    for number, first, title in sections(lines):
        header = []
        for line in lines[first:]:
            if not line.startswith("#"):
                break
            header.append(line)
        start = [i for i, line in enumerate(header) if line.startswith("# Offers:")]
        assert len(start) == 1, f"section {number} ({title}) has no '# Offers:' line"
        text = [header[start[0]].removeprefix("# Offers:")]
        text += [line[1:] for line in header[start[0] + 1:] if line.startswith("#   ")]
        names = " ".join(text).strip().rstrip(".")
        found[number] = [] if names == "nothing" else [n.strip() for n in names.split(",")]
    return found


def public_names(lines=LINES, tree=None) -> dict[int, list[str]]:
    """Each section's public (no leading underscore) top-level names, in the order bound."""
    tree = tree or ast.parse("\n".join(lines))
    banners, found = sections(lines), {}
    for name, lineno in bindings(tree):
        number = section_of(lineno, banners)
        if number and not name.startswith("_") and name not in found.get(number, []):
            found.setdefault(number, []).append(name)
    return found


def test_each_header_says_what_it_offers():
    """The Offers line names exactly the section's public names, in the order it binds them:
    what later sections may use (test_each_section_is_one_room: they use no other)."""
    public = public_names(LINES, TREE)
    assert offered() == {n: public.get(n, []) for n, _, _ in sections()}


def test_the_offers_test_can_fail():
    """A made-up section whose Offers line leaves out a public name, and names a private one."""
    lines = ["# ---- 1. One ---", "#", "# Offers: _hidden, shown.", "def shown():", "    pass",
             "def also():", "    pass", "def _hidden():", "    pass"]
    assert offered(lines) == {1: ["_hidden", "shown"]}
    assert public_names(lines) == {1: ["shown", "also"]}


def annotation_nodes(tree) -> set[int]:
    """The ids of every node inside an annotation (they are never evaluated: from __future__
    import annotations)."""
    roots = []
    for n in ast.walk(tree):
        if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)):
            a = n.args
            roots += [p.annotation for p in a.posonlyargs + a.args + a.kwonlyargs
                      + [p for p in (a.vararg, a.kwarg) if p is not None]] + [n.returns]
        elif isinstance(n, ast.AnnAssign):
            roots.append(n.annotation)
    return {id(m) for r in roots if r is not None for m in ast.walk(r)}


def sections_using(names: set[str], lines=LINES, tree=TREE) -> set[int]:
    """The sections whose code (not their annotations) uses any of `names`, or imports it."""
    banners, skip, found = sections(lines), annotation_nodes(tree), set()
    for node in tree.body:
        here = section_of(node.lineno, banners)
        for n in ast.walk(node):
            if id(n) in skip:
                continue
            if isinstance(n, ast.Name) and n.id in names:
                found.add(here)
            elif isinstance(n, (ast.Import, ast.ImportFrom)) and any(
                    (a.name if isinstance(n, ast.Import) else n.module or "").split(".")[0]
                    in names for a in n.names):
                found.add(here)
    return found


def test_nothing_outside_the_numpy_path_touches_numpy():
    """numpy is imported and used (np.…) in its own section only; the others ask it for what they
    need (angle_array, column_texts, ...). The preamble imports it for annotations only."""
    assert sections_using({"numpy", "np"}) - {0} == set(_section_numbers("The numpy path"))


def test_command_line_code_is_in_the_last_section_only():
    """argparse is used in the last section only (the preamble imports it)."""
    assert sections_using({"argparse"}) - {0} == {len(sections())}


def test_the_usage_tests_can_fail():
    """A made-up section 2 that computes with np, and one that only annotates with numpy."""
    lines = ["# ---- 1. One ---", "def f(x: numpy.ndarray) -> numpy.ndarray:", "    return x",
             "# ---- 2. Two ---", "def g(np):", "    return np.zeros(3)",
             "# ---- 3. Three ---", "def h():", "    import numpy", "    return numpy"]
    assert sections_using({"numpy", "np"}, lines, ast.parse("\n".join(lines))) == {2, 3}


def test_the_module_docstring_names_every_section():
    """The module docstring's contents: "N. title" for every section, the title as the banner has
    it up to its colon, in lower case."""
    doc = " ".join(linkage.__doc__.split()).lower()
    missing = [(n, title) for n, _, title in sections()
               if f"{n}. {title.split(':')[0].lower()}" not in doc]
    assert missing == []


PARSER_CALLS = {"ArgumentParser", "CommandParser", "add_parser", "add_subparsers",
                "add_argument", "add_options", "parse_args"}


def test_only_the_command_line_builds_parsers():
    last = len(sections())
    banners = sections()
    found = []
    for node in ast.walk(TREE):
        if isinstance(node, ast.Call):
            name = getattr(node.func, "attr", None) or getattr(node.func, "id", None)
            if name in PARSER_CALLS and section_of(node.lineno, banners) != last:
                found.append((node.lineno, name))
    assert found == []


def _mutable(value) -> bool:
    return isinstance(value, (ast.List, ast.Dict, ast.Set, ast.ListComp, ast.DictComp,
                              ast.SetComp)) or (isinstance(value, ast.Call) and getattr(
                                  value.func, "id", None) in ("list", "dict", "set"))


def test_no_state_that_a_second_caller_could_see():
    """No module-level mutable container but the declared tables (UPPER_CASE names, filled once
    at import), and none in a class body (a class attribute list is shared by every caller, as
    Single.errors was)."""
    found = []
    for node in TREE.body:
        targets = (node.targets if isinstance(node, ast.Assign) else [node.target]
                   if isinstance(node, ast.AnnAssign) else [])
        value = getattr(node, "value", None)
        for target in targets:
            if isinstance(target, ast.Name) and value is not None and _mutable(value) \
                    and not target.id.isupper():
                found.append((node.lineno, target.id))
        if isinstance(node, ast.ClassDef):
            for item in node.body:
                value = getattr(item, "value", None)
                if isinstance(item, (ast.Assign, ast.AnnAssign)) and value is not None \
                        and _mutable(value):
                    found.append((item.lineno, f"{node.name}.<class attribute>"))
    assert found == []


def unannotated(lines=LINES, tree=TREE, numbers=None) -> list[str]:
    """The public functions and methods of sections `numbers` (every section if None) with a
    parameter or a return not annotated (self and cls excepted), as "name (line): what is
    missing"."""
    banners, found = sections(lines), []

    def visit(node, prefix):
        for n in ast.iter_child_nodes(node):
            if isinstance(n, ast.ClassDef):
                visit(n, f"{prefix}{n.name}.")
            elif isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)):
                if (numbers is None or section_of(n.lineno, banners) in numbers) \
                        and not n.name.startswith("_"):
                    a = n.args
                    params = a.posonlyargs + a.args + a.kwonlyargs + [
                        p for p in (a.vararg, a.kwarg) if p is not None]
                    missing = [p.arg for p in params
                               if p.annotation is None and p.arg not in ("self", "cls")]
                    missing += ["return"] * (n.returns is None)
                    if missing:
                        found.append(f"{prefix}{n.name} ({n.lineno}): {', '.join(missing)}")
    visit(tree, "")
    return found


def test_every_public_function_is_annotated():
    """Every public function and method of every section says the types of its parameters and
    its return; the type checker holds them to the code (below)."""
    assert unannotated() == []


@pytest.mark.slow          # --quick leaves it out: mypy
def test_the_type_checker_finds_nothing():
    """mypy (pinned in the test dependencies; its options in pyproject.toml's [tool.mypy]) on
    linkage.py: no error."""
    done = subprocess.run([sys.executable, "-m", "mypy"], cwd=Path(linkage.__file__).parent,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout[-3000:]


def test_the_annotation_test_can_fail():
    """In a made-up file, the public functions of sections 5-8 that lack an annotation are found:
    not the annotated, the private, nor those of section 9 (when only 5-8 are asked)."""
    lines = ["# ---- 5. The engine ---", "def reach(x, *rest) -> int:", "    return 0",
             "def kept(x: int) -> int:", "    return x", "def _own(x):", "    return x",
             "class K:", "    def m(self, y):", "        return y",
             "# ---- 9. Benchmarks ---", "def later(x):", "    return x"]
    found = unannotated(lines, ast.parse("\n".join(lines)), numbers=(5, 6, 7, 8))
    assert found == ["reach (2): x, rest", "K.m (9): y, return"]


# A name a docstring mentions as code: `name` in backquotes, or name() with empty parentheses.
MENTION = re.compile(r"`([A-Za-z_]\w*(?:\.[A-Za-z_]\w*)*)(?:\(\))?`|"
                     r"(?<![\w.$])([A-Za-z_]\w*(?:\.[A-Za-z_]\w*)*)\(\)")
NOT_PYTHON = {"fg"}         # the shell's command (single_keys: Ctrl-Z, then `fg`)


def unknown_mentions(tree=TREE) -> list[str]:
    """The names docstrings mention that the program nowhere has: each must be a name it
    defines, binds or uses (a function, class, method, attribute, parameter, variable), a
    string it uses (a command, a column, an extra), a builtin or a standard module; a dotted
    name's last part an attribute of what its first part names (a class, module or module
    of the standard library) or, failing that, one the program defines. BASIC's upper-case
    functions (TAN(), CVS) are the listing's."""
    known: set[str] = set(dir(builtins)) | set(sys.stdlib_module_names) | NOT_PYTHON
    documented = [n for n in ast.walk(tree) if isinstance(
        n, (ast.Module, ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef))]
    docstrings = {id(n.body[0].value) for n in documented if ast.get_docstring(n) is not None}
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            known.add(node.name)
        elif isinstance(node, ast.Name):
            known.add(node.id)
        elif isinstance(node, ast.arg):
            known.add(node.arg)
        elif isinstance(node, ast.Attribute):
            known.add(node.attr)
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and \
                id(node) not in docstrings:
            known.update(re.findall(r"[A-Za-z_]\w*", node.value))
    found = []
    for node in documented:
        for m in MENTION.finditer(ast.get_docstring(node, clean=False) or ""):
            first, *rest = (m[1] or m[2]).split(".")
            if re.fullmatch(r"[A-Z]{2,6}", first):
                continue
            owner = getattr(linkage, first, None) or sys.modules.get(first)
            if first not in known or (rest and not hasattr(owner, rest[-1])
                                      and rest[-1] not in known):
                found.append(f"{getattr(node, 'name', 'module')} ({getattr(node, 'lineno', 1)})"
                             f": {m[1] or m[2]}")
    return found


def test_the_names_docstrings_mention_exist():
    """Every docstring names only what is there (a `commit()` promised where the method is
    finish() is found)."""
    assert unknown_mentions() == []


def test_the_mention_test_can_fail():
    """A made-up docstring that promises commit() and `Temporary.close_all` is caught; one that
    names finish() and `os.replace`, both real, is not."""
    tree = ast.parse('class T:\n    """Write, then commit(); see `Temporary.close_all`, finish() and'
                     ' `os.replace`."""\n    def finish(self):\n        pass\n')
    assert unknown_mentions(tree) == ["T (1): commit", "T (1): Temporary.close_all"]


def test_no_module_level_name_is_bound_twice():
    """One name per thing: a second `CLIPPED = ...` in a later section silently replaced the
    first for every function that read it (a figure's legend said 'accelerationclipped')."""
    first: dict[str, int] = {}
    twice = [f"{name} ({first[name]}, {lineno})" for name, lineno in bindings()
             if first.setdefault(name, lineno) != lineno]
    assert twice == []


def test_the_menus_linkages_are_the_engines_kinds():
    """KIND_MENU (the original program's menu: its keys and the order it asks for the
    dimensions) has the five kinds, in the menu's order."""
    assert list(linkage.KIND_MENU) == list(linkage.KIND_NAMES) == [
        linkage.PLANE_FOUR_BAR, linkage.SPHERICAL_FOUR_BAR, linkage.SKEW_FOUR_BAR,
        linkage.PLANE_SLIDER_CRANK, linkage.SKEW_SLIDER_CRANK]


def pyflakes(*paths: Path) -> str:
    """What pyflakes (pinned in the test dependencies) says of these files."""
    need("pyflakes", load=False)
    return subprocess.run([sys.executable, "-m", "pyflakes", *map(str, paths)],
                          capture_output=True, text=True, timeout=300).stdout


def test_pyflakes_finds_nothing():
    """No unused import or variable, no undefined name, in the program or its tests."""
    root = Path(linkage.__file__).parent
    assert pyflakes(root / "linkage.py", *sorted((root / "tests").glob("**/*.py"))) == ""


def test_pyflakes_can_fail(tmp_path):
    made_up = tmp_path / "made_up.py"
    made_up.write_text("import os\n\n\ndef f():\n    return undefined_name\n")
    said = pyflakes(made_up)
    assert "'os' imported but unused" in said and "undefined name 'undefined_name'" in said


def test_each_named_tuple_is_the_class_typing_makes():
    """linkage makes `class X(NamedTuple):` at run time without typing (_NamedTupleType, for the
    start-up): each of its classes, its source made again by typing.NamedTuple, has the same
    fields, defaults, docstring, methods, module and annotations (as written: typing keeps
    them as ForwardRefs of the same text)."""
    import __future__
    import typing
    space = dict(vars(linkage), NamedTuple=typing.NamedTuple)
    classes = [node for node in TREE.body if isinstance(node, ast.ClassDef)
               and [ast.unparse(base) for base in node.bases] == ["NamedTuple"]]
    assert len(classes) > 70
    for node in classes:
        exec(compile(ast.Module([node], []), "linkage.py", "exec",
                     __future__.annotations.compiler_flag, dont_inherit=True), space)
        want, got = space[node.name], getattr(linkage, node.name)
        assert got is not want and issubclass(got, tuple), node.name
        for attribute in ("_fields", "_field_defaults", "__doc__", "__module__", "__qualname__",
                          "__new__.__defaults__"):
            first, _, second = attribute.partition(".")
            assert (getattr(getattr(got, first), second) if second else getattr(got, first)) == (
                getattr(getattr(want, first), second) if second else getattr(want, first)), (
                    node.name, attribute)
        assert set(vars(got)) == set(vars(want)) - {"__orig_bases__"}, node.name   # typing's
        #   record of the bases as written (typing.NamedTuple, a function): nothing reads it
        assert got.__annotations__ == {
            k: v.__forward_arg__ for k, v in want.__annotations__.items()}, node.name


def test_main_freezes_the_collector_only_as_the_process_command_line():
    """main(argv) called in a process of its own making (tests, a caller) leaves the cyclic
    collector as it was: gc.freeze is for the process's own command line (argv None) only."""
    import gc
    before = gc.get_freeze_count()
    assert linkage.main(["scene", "--list"]) == 0
    assert gc.get_freeze_count() == before
