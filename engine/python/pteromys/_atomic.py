"""Atomic output files for the Python side (issue 9, docs/reliability.md):
write to a temporary file beside the target, flush it to disk and rename it
into place, so a failure or a kill leaves the old file or the new one, never
a fragment."""
import os
import tempfile


def _tmp_beside(path, suffix):
    d = os.path.dirname(os.path.abspath(path)) or "."
    fd, tmp = tempfile.mkstemp(prefix=os.path.basename(path) + ".tmp-", suffix=suffix, dir=d)
    return fd, tmp


def _commit(tmp, path):
    with open(tmp, "rb") as f:
        os.fsync(f.fileno())
    os.replace(tmp, path)


def write_text(path, text, encoding="utf-8"):
    """Writes text to path atomically."""
    fd, tmp = _tmp_beside(path, "")
    try:
        with os.fdopen(fd, "w", encoding=encoding) as f:
            f.write(text)
        _commit(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


def savefig(fig, path, **kwargs):
    """fig.savefig(path, ...) atomically (the format comes from path's extension)."""
    ext = os.path.splitext(path)[1]
    fd, tmp = _tmp_beside(path, ext)
    os.close(fd)
    try:
        kwargs.setdefault("format", ext[1:] if ext else None)
        fig.savefig(tmp, **kwargs)
        _commit(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise
