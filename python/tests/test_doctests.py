"""Every example in the package's docstrings runs and prints what it says
(doctest), so the documentation cannot drift from the code."""
import doctest
import importlib
import pkgutil

import pytest

import treetrace


def _modules():
    names = ["treetrace"]
    for info in pkgutil.walk_packages(treetrace.__path__, "treetrace."):
        if info.name.endswith("__main__"):
            continue
        names.append(info.name)
    return names


@pytest.mark.parametrize("name", _modules())
def test_docstring_examples(name, monkeypatch, tmp_path):
    monkeypatch.chdir(tmp_path)  # examples that write files write them here
    module = importlib.import_module(name)
    flags = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
    result = doctest.testmod(module, optionflags=flags, verbose=False)
    assert result.failed == 0, "%d of %d examples in %s failed (see the output above)" % (
        result.failed, result.attempted, name)


def test_public_api_documented_with_examples():
    """Each public class, function and method has a docstring with an
    example (plain properties are described by their class's)."""
    missing = []
    for name in treetrace.__all__:
        obj = getattr(treetrace, name)
        if not callable(obj) or isinstance(obj, type) and issubclass(obj, BaseException):
            continue
        items = [(name, obj)]
        if isinstance(obj, type):
            for attr, member in vars(obj).items():
                if attr.startswith("_"):
                    continue
                items.append(("%s.%s" % (name, attr), member))
        for label, item in items:
            if isinstance(item, (classmethod, staticmethod)):
                item = item.__func__
            if isinstance(item, property) or not callable(item):
                continue
            doc = getattr(item, "__doc__", None) or ""
            if ">>>" not in doc:
                missing.append(label)
    assert not missing, "no example in the docstring of: " + ", ".join(sorted(missing))
