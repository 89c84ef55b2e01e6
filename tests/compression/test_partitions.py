"""The partition table: each name the command line offers is implemented by one module, in the header's order."""
import importlib
import pkgutil

import pytest

import ifslib.compression
from ifslib.compression.config import CodeOptions
from ifslib.compression.encode import encode
from ifslib.compression.fileformat import from_bytes, to_bytes
from ifslib.compression.partitions import partition_of, table
from ifslib.names import PARTITIONS
from compression_images import photo


def test_each_named_partition_has_one_module_and_the_table_keeps_the_names_order():
    defined = [getattr(importlib.import_module(f"ifslib.compression.{m.name}"), "PARTITION", None)
               for m in pkgutil.iter_modules(ifslib.compression.__path__)]
    names = [entry.name for entry in defined if entry is not None]
    assert sorted(names) == sorted(PARTITIONS) and len(set(names)) == len(names)
    assert list(table()) == list(PARTITIONS)  # a file's header numbers them in this order
    assert all(entry.name == name for name, entry in table().items())


@pytest.mark.parametrize("name", list(PARTITIONS))
def test_each_partition_codes_and_reads_back_its_own_code(name):
    options = CodeOptions(min_block=4, max_block=16, partition=name)
    code = encode(photo(32, seed=3), options, bpp=1.0)
    back = from_bytes(to_bytes(code))
    assert partition_of(back.options) is table()[name]
    assert (back.block_height is not None) == table()[name].rectangles
    for field in ("y", "x", "size", "domain", "iso", "s_idx", "m_idx"):
        assert getattr(back, field).tolist() == getattr(code, field).tolist()
