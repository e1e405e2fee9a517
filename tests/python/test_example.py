"""examples/python/uts_count.py runs and agrees with numpy, and
docs/python.md shows it as it is."""
import os
import re
import subprocess
import sys


def example(source_root):
    return os.path.join(source_root, 'examples', 'python', 'uts_count.py')


def test_uts_count(source_root):
    result = subprocess.run([sys.executable, example(source_root), '6'], capture_output=True, text=True,
                            timeout=600)
    assert result.returncode == 0, result.stdout + result.stderr
    assert re.match(r'9627 nodes in [0-9.]+ s on .* \(megakernel/stealing\)\n', result.stdout)
    assert 'nodes per depth: 1 2 37 106 434 1776 7271\nnumpy counts the same\n' in result.stdout


def test_docs_show_the_example(source_root):
    with open(os.path.join(source_root, 'docs', 'python.md'), encoding='utf-8') as f:
        docs = f.read()
    with open(example(source_root), encoding='utf-8') as f:
        script = f.read()
    assert '```python\n' + script + '```\n' in docs
