"""The coder's options are checked where they enter."""
import pytest

from ifslib.compression.config import CodeOptions, RefineOptions
from ifslib.errors import IFSError


def test_sizes_run_from_largest_to_smallest():
    assert CodeOptions(min_block=4, max_block=32).sizes == [32, 16, 8, 4]


@pytest.mark.parametrize("kwargs, words", [
    ({"min_block": 6}, "power of two"), ({"max_block": 256}, "power of two"), ({"min_block": 2}, "power of two"),
    ({"min_block": 16, "max_block": 8}, "must not exceed"), ({"s_bits": 1}, "s_bits"), ({"m_bits": 12}, "m_bits"),
    ({"s_max": 1.0}, "|s| < 1"), ({"s_max": 0}, "s_max"), ({"min_block": True}, "power of two")])
def test_bad_code_options_say_what_to_change(kwargs, words):
    with pytest.raises(IFSError, match=words.replace("|", r"\|")):
        CodeOptions(**kwargs)


@pytest.mark.parametrize("kwargs", [{"searches": -1}, {"steps": 1.5}, {"lr": 0}, {"steps": True}, {"repartitions": -1}])
def test_bad_refine_options(kwargs):
    with pytest.raises(IFSError):
        RefineOptions(**kwargs)
