"""The code blocks of README.md marked `<!-- example: NAME ... -->`."""
import os
import re
import sys


def example(readme, name):
    text = open(readme, encoding="utf-8").read()
    m = re.search(r"<!-- example: %s\b[^>]*-->\s*```[a-z]*\n(.*?)```" % re.escape(name), text,
                  re.S)
    if not m:
        raise LookupError("README.md has no example %s" % name)
    return m.group(1)


if __name__ == "__main__":  # README.md NAME: print the block
    sys.stdout.write(example(sys.argv[1], sys.argv[2]))
