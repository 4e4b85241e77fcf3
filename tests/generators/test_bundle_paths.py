"""check_paths refuses a path that another path needs as a folder (in any case), and
paths that are not plain, and accepts paths that only share a prefix of characters."""

from __future__ import annotations

import pytest

from spl.generators.bundle.paths import BundlePathClash, check_paths


@pytest.mark.parametrize(
    "paths",
    [
        ["a/b", "a/b/c"],
        ["a/b/c", "a/b"],
        ["x", "x/y/z"],
        ["A/b", "a/B/c"],
        ["ros2/launch.xml", "ROS2/LAUNCH.XML/more"],
    ],
)
def test_a_file_that_is_the_folder_of_another_is_refused(paths):
    with pytest.raises(BundlePathClash, match="is a file and the folder of another"):
        check_paths(paths)


@pytest.mark.parametrize("path", ["/abs", "a//b", "a/./b", "a/../b", "a/", ""])
def test_a_path_that_is_not_plain_is_refused(path):
    with pytest.raises(BundlePathClash, match="not a plain relative path"):
        check_paths(["ok", path])


def test_paths_sharing_characters_but_no_folder_are_accepted():
    check_paths(["a/b", "a/bc", "ab/c", "a/b.d/e", "manifest.json", "x"])
