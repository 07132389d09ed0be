"""The README's pluto_nav example runs as written and prints what it says."""

import contextlib
import io
import pathlib
import re

README = pathlib.Path(__file__).resolve().parents[3] / 'README.md'


def test_readme_example_localizes_the_laser_and_finds_the_wall():
    text = README.read_text()
    (code,) = re.findall(r'<!-- example: pluto_nav -->\n```python\n(.*?)```', text, re.S)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, 'README.md', 'exec'), {})
    assert out.getvalue().splitlines() == ['4 True [4.  3.  0.1]', '89 -0.1 6.0']
