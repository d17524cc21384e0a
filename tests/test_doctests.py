"""The Examples sections of the public modules run as written."""

import doctest
import importlib

import pytest


@pytest.mark.parametrize("name", ["gfrf", "gfrf.model.equation", "gfrf.kernels.recursion",
                                  "gfrf.kernels.combinatorics",
                                  "gfrf.model.template"])
def test_module_examples(name):
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.ELLIPSIS)
    assert result.attempted > 0
    assert result.failed == 0
