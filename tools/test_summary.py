"""Print one closing line for the whole `make test` run, from colcon's JUnit result files.

colcon runs each package's pytest separately; this adds their JUnit reports up so that the last
line of `make test` says how many tests ran in all: ``total: N passed, N failed, N skipped``.
Exits 1 when anything failed or errored, or when no test ran at all.
"""

from __future__ import annotations

import pathlib
import sys

from lxml import etree


def main(build_dir: str) -> int:
    passed = failed = skipped = 0
    build = pathlib.Path(build_dir)
    # ament_cmake_pytest writes test_results/<pkg>/*.xunit.xml, ament_python's pytest pytest.xml
    # (<pkg>/pytest.xml, or test-<lane>/<pkg>/pytest.xml for a package split over two lanes).
    reports = (sorted(build.glob('*/test_results/**/*.xunit.xml')) + sorted(build.glob('*/pytest.xml'))
               + sorted(build.glob('test-*/*/pytest.xml')))
    for report in reports:
        root = etree.parse(str(report), etree.XMLParser(resolve_entities=False, no_network=True))
        suites = [root.getroot()] if root.getroot().tag == 'testsuite' else root.findall('testsuite')
        for suite in suites:
            tests = int(suite.get('tests', 0))
            bad = int(suite.get('failures', 0)) + int(suite.get('errors', 0))
            skip = int(suite.get('skipped', 0))
            failed += bad
            skipped += skip
            passed += tests - bad - skip
    print(f'{len(reports)} test report(s) under {build_dir}/')
    print(f'total: {passed} passed, {failed} failed, {skipped} skipped')
    return 1 if failed or passed == 0 else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else 'build'))
