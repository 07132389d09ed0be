"""The README is a door and the manual a site (issue 40): the README stays one screen long, every
section the README once held is a heading of the manual, every page is in the site's navigation,
every link between the README and the pages reaches a file and a heading, every runnable example is
named once and run by a test, and the README's two commands are what the Makefile and CI run.

``make docs`` (mkdocs, strict) checks the site's links too, but it needs its own environment and is
not part of ``make test``; these checks need nothing but the files.
"""

from __future__ import annotations

import re
import unicodedata

from wurde_testing.manual import MARKER, headings, pages, repository_root

ROOT = repository_root()
LINK = re.compile(r'!?\[[^\]]*\]\(([^)\s]+)\)')

#: The README's headings before the manual moved to docs/ (main at 9cf98ce): each is now a heading
#: of a page of docs/, so no part of the old README was lost on the way.
README_HEADINGS_BEFORE_THE_MOVE = (
    'WURDE and Pluto on ROS 2 Jazzy',
    'The two commands',
    'A shell for running things by hand',
    'Building with ROS 2 Jazzy from apt (Ubuntu 24.04)',
    'Layout',
    'Interfaces (`wurde_interfaces`)',
    'Adding an interface in your own package',
    'tf2_msgs: a stand-in where the ROS install lacks it',
    'Programming with wurde_core',
    'The MCP (`wurde_mcp`)',
    "Pluto's xmlServer (`xml_server`)",
    "CARMEN's parameters (`param_daemon`, `param_tool`, `wurde_core.carmen_param`)",
    'Recording and replay (`record`, `replay`)',
    'A live view in Foxglove (`live_view`)',
    'The simulated robot and the drivers (`wurde_drivers`)',
    'Vision (`vision_module`)',
    'The Eye (`eye`, WURDE 7.8)',
    'Navigation (`pluto_nav`)',
    "CARMEN's map server (`map_server`)",
    'Maps users already have',
    'How good it is',
    "Real robots' data: CARMEN logs, rosbag2 bags, live ROS 2 robots",
    'The estimation core (`pluto_nav`, no ROS)',
    'Movement (`pluto_motion`)',
    'How well it moves',
    'Among people (issue 38, partly done)',
    "CARMEN's navigator (`navigator`)",
    "CARMEN's robot-program API (`pluto_motion.carmen`)",
    'Keyboard programs (Pluto 5)',
    "The guide's movers: SynchroMover and LaserAvoider (WURDE 7.3, 7.7)",
    'Teleoperation (`blind_teleop`, `joystick_emulator`)',
    'Using it from ROS 2',
    'Many machines: one MCP per host',
    'Keeping strangers out (DDS Security)',
    'WURDE names and ours',
    'Benchmarks',
    'Tests',
    'How the set-up works',
)


def slug(title: str) -> str:
    """A heading's anchor as mkdocs makes it (Python-Markdown's ``toc`` slugify), which is also
    GitHub's for the headings of this repository (no two spaces or dashes in a row)."""
    text = unicodedata.normalize('NFKD', title).encode('ascii', 'ignore').decode('ascii')
    text = re.sub(r'[^\w\s-]', '', text).strip().lower()
    return re.sub(r'[-\s]+', '-', text)


def _outside_code(text: str) -> str:
    """The text with fenced code blocks and inline code blanked (a link there is not a link)."""
    kept, inside = [], False
    for line in text.splitlines():
        if re.match(r'\s*```', line):
            inside = not inside
            continue
        kept.append('' if inside else re.sub(r'`[^`]*`', '', line))
    return '\n'.join(kept)


def test_the_readme_is_one_screen_to_a_running_robot():
    lines = (ROOT / 'README.md').read_text().splitlines()
    assert len(lines) <= 200, f'README.md has {len(lines)} lines; the manual (docs/) holds the rest'


def test_every_heading_of_the_old_readme_is_in_the_manual():
    titles = {title for page in pages(ROOT)[1:] for _, _, title in headings(page.read_text())}
    missing = [title for title in README_HEADINGS_BEFORE_THE_MOVE if title not in titles]
    assert not missing, f'headings of the README that no page of docs/ has: {missing}'


def test_every_page_is_in_the_sites_navigation_and_every_entry_is_a_page():
    config = (ROOT / 'mkdocs.yml').read_text()
    listed = re.findall(r'^\s*- (?:"[^"]*"|[^:\n]+): ([\w./-]+\.md)\s*$', config, re.M)
    on_disk = sorted(page.name for page in (ROOT / 'docs').glob('*.md'))
    assert sorted(listed) == on_disk


def test_every_link_of_the_readme_and_the_manual_reaches_a_file_and_a_heading():
    broken = []
    for page in pages(ROOT):
        for target in LINK.findall(_outside_code(page.read_text())):
            if re.match(r'[a-z]+:', target):
                continue                                   # https:, mailto: — not ours to check
            path, _, anchor = target.partition('#')
            file = (page.parent / path).resolve() if path else page
            if not file.is_file():
                broken.append(f'{page.relative_to(ROOT)}: {target} (no such file)')
            elif anchor and anchor not in {slug(title) for _, _, title in headings(file.read_text())}:
                broken.append(f'{page.relative_to(ROOT)}: {target} (no such heading)')
    assert not broken, '\n'.join(broken)


def test_every_example_is_named_once_and_run_by_a_test():
    names = [match.group(1) for page in pages(ROOT) for match in MARKER.finditer(page.read_text())]
    assert len(names) == len(set(names)), sorted(name for name in names if names.count(name) > 1)
    tests = '\n'.join(path.read_text() for path in ROOT.glob('src/**/test/test_*.py'))
    unrun = [name for name in names if f"'{name}'" not in tests]
    assert not unrun, f'examples no test reads: {unrun}'


def test_the_readmes_two_commands_are_the_makefiles_and_ci_runs_the_test_command():
    text = (ROOT / 'README.md').read_text()
    block = re.search(r'## The two commands\n.*?```bash\n(.*?)```', text, re.S).group(1)
    commands = [line.split('#', 1)[0].strip() for line in block.splitlines() if line.strip()]
    assert commands == ['make demo', 'make test']
    makefile = (ROOT / 'Makefile').read_text()
    assert re.search(r'^demo: ', makefile, re.M) and re.search(r'^test: ', makefile, re.M)
    ci = [line for line in (ROOT / '.ci' / 'run').read_text().splitlines()
          if line.strip() and not line.startswith(('#', 'set ', 'cd '))]
    assert ci == ['make test']
