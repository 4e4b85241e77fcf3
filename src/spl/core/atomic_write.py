"""Writing one output file whole or not at all (feature models by ``spl convert``,
diagrams by ``spl render``): the bytes go to a temporary sibling renamed into place, so
a reader never sees half a file and a failure leaves the old one.

The temporary file is created private (0600, as ``mkstemp`` must); before the rename it
gets the mode any new file would get under the user's umask, as ``open`` gives (a
diagram written 0600 could not be served by a web server or read by a colleague).
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path


def write_atomically(path: Path, data: bytes) -> None:
    """``path`` holds ``data`` afterwards, or is untouched when writing failed."""
    directory = path.parent if str(path.parent) else Path(".")
    handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", dir=directory)
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
        os.chmod(temporary, 0o666 & ~_umask())
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


def _umask() -> int:
    mask = os.umask(0o022)  # the only way to read it is to set it
    os.umask(mask)
    return mask
