"""A bag that cannot even be started on a full disk leaves nothing behind: no directory holding a torn header that
readers would take for a bag. The recorder then says it could not create the bag (exit 6), and that is all."""

import errno

import pytest

from joshua_runtime.bags.bag_writer import BagWriter
from testsupport.small_filesystem import fill, small_filesystem

pytestmark = pytest.mark.process  # mount(8) of a small tmpfs


def test_a_bag_whose_first_write_fails_leaves_no_directory_behind(tmp_path):
    with small_filesystem(tmp_path / "small") as small:
        fill(small)
        with pytest.raises(OSError) as failure:
            BagWriter(small / "run_0")
        assert failure.value.errno == errno.ENOSPC
        assert sorted(path.name for path in small.iterdir()) == ["filler"]
