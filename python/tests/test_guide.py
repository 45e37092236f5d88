"""The guide's Python runs: every ``python`` block of docs/guide/*.md is executed from the
repository's root (the Rust suite's tests/guide_commands.rs runs its commands and scenes),
so a page cannot drift from the package."""

import re

import pytest

from conftest import ROOT

BLOCKS = [
    pytest.param(code, id=f"{page.name}:{k}")
    for page in sorted((ROOT / "docs" / "guide").glob("*.md"))
    for k, code in enumerate(re.findall(r"```python\n(.*?)```", page.read_text(), re.S))
]


def test_the_guide_has_python():
    assert BLOCKS, "no python block in docs/guide"


@pytest.mark.parametrize("code", BLOCKS)
def test_a_guide_block_runs(code, capsys):
    exec(compile(code, "guide", "exec"), {})
    capsys.readouterr()
