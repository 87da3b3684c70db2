"""Writing outputs so that nothing the user owns is lost.

Every file and folder hairlod writes is built under a temporary name beside its target and moved into
place only when complete, so a target is either the old one or the new one, never a mixture:

- replacing_file(path): a file is replaced by os.replace of a finished temporary file.
- replace_folder(target, kind, write): a folder is replaced only when it is a folder of the same
  kind that hairlod wrote (its manifest.json says so, and it holds only the files that manifest
  names); anything else at the target is refused with OutputFolderError before any work is lost.
  The finished folder is swapped in with one atomic rename (renameat2 RENAME_EXCHANGE where the
  kernel has it), so concurrent writers of one target end with one complete result.

Temporaries are named ``.NAME.hairlod-PID-TOKEN.tmp`` (the C++ hair-file writer uses the same
scheme: cpp/src/io/hair_file.cpp), so a later write of the same target recognises those whose
process has ended (killed, crashed) and removes them, and a signal handler can remove its own
process's ones (remove_own_temporaries, called by the CLI on SIGINT / SIGTERM).
"""

import ctypes
import errno
import os
import re
import secrets
import shutil
import threading
from contextlib import contextmanager

from . import strict_json

__all__ = ["MANIFEST", "OutputFolderError", "begin_writing", "check_folder_target", "completed", "files_named", "installing",
           "remove_own_temporaries", "stop_writing", "remove_stale_temporaries",
           "replace_folder", "replacing_file", "temporary_path"]

MANIFEST = "manifest.json"

# Parents of targets this process writes into: remove_own_temporaries() looks there.
_parents_in_use = set()
# Held while a temporary becomes a target (and while the replaced folder is removed), and while a
# staging folder is made: stop_writing() takes it for good, so a signal handler never removes a
# folder that a worker thread is swapping into place, and no later install starts.
_installing = threading.RLock()
# Targets this process has completed (for the CLI's message on a signal).
_completed = []


class OutputFolderError(ValueError):
    """An output target that hairlod must not replace (a ValueError: bad input)."""


def temporary_path(target):
    """A fresh temporary name beside `target` (same folder, so the final rename stays on one file
    system), recognisable by remove_stale_temporaries()."""
    parent, name = os.path.split(os.path.abspath(target))
    _parents_in_use.add(parent)
    return os.path.join(parent, f".{name}.hairlod-{os.getpid()}-{secrets.token_hex(8)}.tmp")


def begin_writing(target):
    """For a writer that makes its own temporaries by the same scheme (the C++ hair-file writer):
    removes stale temporaries of `target` and lets remove_own_temporaries() find this process's."""
    _parents_in_use.add(os.path.dirname(os.path.abspath(target)))
    remove_stale_temporaries(target)


def _temporary_pattern(name):
    return re.compile(rf"^\.{re.escape(name)}\.hairlod-(\d+)-[0-9a-f]+\.tmp$")


def _process_start_time(pid):
    """Seconds since the epoch at which process `pid` started; None when it does not exist."""
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii", errors="replace") as stat:
            fields = stat.read().rsplit(")", 1)[1].split()
        with open("/proc/stat", encoding="ascii") as system:
            boot = next(float(line.split()[1]) for line in system if line.startswith("btime "))
        return boot + int(fields[19]) / os.sysconf("SC_CLK_TCK")
    except FileNotFoundError:
        return None
    except (OSError, ValueError, IndexError, StopIteration):
        # No /proc: the process exists or not, its start time is unknown.
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return None
        except PermissionError:
            pass
        return float("-inf")


def _remove(path):
    if os.path.isdir(path) and not os.path.islink(path):
        shutil.rmtree(path, ignore_errors=True)
    else:
        try:
            os.unlink(path)
        except FileNotFoundError:
            pass


def remove_stale_temporaries(target):
    """Removes the temporaries of `target` left by processes that no longer run (a process that
    started after a temporary was last changed reuses its id: that temporary is stale too).
    Returns the paths removed."""
    parent, name = os.path.split(os.path.abspath(target))
    pattern = _temporary_pattern(name)
    removed = []
    try:
        entries = os.listdir(parent)
    except OSError:
        return removed
    for entry in entries:
        match = pattern.match(entry)
        if not match or int(match.group(1)) == os.getpid():
            continue
        path = os.path.join(parent, entry)
        try:
            changed = os.lstat(path).st_mtime
        except FileNotFoundError:
            continue
        started = _process_start_time(int(match.group(1)))
        if started is None or started > changed + 1.0:
            _remove(path)
            removed.append(path)
    return removed


def remove_own_temporaries():
    """Removes every temporary this process made. Each is first renamed, so that a thread still
    writing into a staging folder by its path fails instead of refilling it while it is removed."""
    suffix = re.compile(rf"^\.(.+)\.hairlod-{os.getpid()}-[0-9a-f]+\.tmp$")
    for parent in list(_parents_in_use):
        try:
            entries = os.listdir(parent)
        except OSError:
            continue
        for entry in entries:
            match = suffix.match(entry)
            if not match:
                continue
            doomed = temporary_path(os.path.join(parent, match.group(1)))
            try:
                os.rename(os.path.join(parent, entry), doomed)
            except OSError:
                continue
            _remove(doomed)


def stop_writing():
    """For a process about to exit on a signal while another thread may still be writing: waits for
    an install in progress to finish, keeps every later one from starting (the lock is never
    released), removes this process's temporaries and returns the targets it completed."""
    _installing.acquire()
    remove_own_temporaries()
    # Files completed inside a staging folder (an LoD's level files) were removed with it.
    return [target for target in _completed if ".hairlod-" not in target]


def completed(target):
    """Records that `target` now holds a complete result of this process."""
    _completed.append(os.path.abspath(os.fspath(target)))


@contextmanager
def installing():
    """Holds the install lock (see stop_writing) around a writer that moves its own temporary into
    place, such as the C++ hair-file writer."""
    with _installing:
        yield


def _umask():
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except OSError:
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


@contextmanager
def replacing_file(path):
    """Yields a temporary path to write; when the block ends without an exception the file replaces
    `path` (mode 0666 less the umask, as a plain open() would give), otherwise it is removed."""
    path = os.path.abspath(os.fspath(path))
    if os.path.isdir(path):
        raise OutputFolderError(f"{path}: is a folder, not a file")
    parent = os.path.dirname(path)
    if not os.path.isdir(parent):
        raise OutputFolderError(f"{path}: folder {parent} does not exist")
    begin_writing(path)
    temporary = temporary_path(path)
    try:
        yield temporary
        with _installing:
            os.chmod(temporary, 0o666 & ~_umask())
            os.replace(temporary, path)
            completed(path)
    finally:
        with _installing:
            _remove(temporary)


def _contains(folder, path):
    """True when `path` is `folder` or lies inside it (both real paths)."""
    return path == folder or path.startswith(folder.rstrip(os.sep) + os.sep)


def files_named(manifest):
    """Every file name a hairlod manifest refers to ("file" and "hair_file" values, at any depth)."""
    names, stack = set(), [manifest]
    while stack:
        value = stack.pop()
        if isinstance(value, dict):
            for key, item in value.items():
                if key in ("file", "hair_file") and isinstance(item, str):
                    names.add(item)
                else:
                    stack.append(item)
        elif isinstance(value, list):
            stack.extend(value)
    return names


def _not_replaceable(folder, kind):
    """Why `folder` is not a folder of `kind` that hairlod wrote, or None when it is one."""
    # Read through one descriptor, so the listing and the manifest come from one folder; and again
    # when that folder is no longer the one at the path (a concurrent writer swapped its own in and
    # is removing the old one, which would look half empty).
    for _ in range(100):
        try:
            descriptor = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
        except OSError as error:
            return f"it cannot be read ({error.strerror})"
        try:
            reason = _folder_reason(descriptor, kind)
            opened, now = os.fstat(descriptor), os.stat(folder)
        except FileNotFoundError:
            continue
        finally:
            os.close(descriptor)
        if (opened.st_dev, opened.st_ino) == (now.st_dev, now.st_ino):
            return reason
    return "it keeps changing while being read"


def _folder_reason(descriptor, kind):
    entries = set(os.listdir(descriptor))
    if MANIFEST not in entries:
        return f"it has no {MANIFEST}" if entries else None
    try:
        manifest_descriptor = os.open(MANIFEST, os.O_RDONLY, dir_fd=descriptor)
        with os.fdopen(manifest_descriptor, "rb") as stream:
            manifest = strict_json.loads(stream.read(), MANIFEST)
    except (OSError, ValueError):
        return f"its {MANIFEST} is not one hairlod wrote"
    written = manifest.get("format") if isinstance(manifest, dict) else None
    if not isinstance(written, str) or not written.startswith(kind):
        return f"its {MANIFEST} is not a {kind} manifest"
    others = sorted(entries - files_named(manifest) - {MANIFEST})
    if others:
        shown = ", ".join(others[:3]) + (", ..." if len(others) > 3 else "")
        return f"it holds files hairlod did not write there ({shown})"
    return None


def check_folder_target(target, kind, force=False, inputs=(), what=None):
    """Raises OutputFolderError when replace_folder(target, kind, ...) must not replace `target`;
    `what` names the kind in messages ("an LoD folder")."""
    real = os.path.realpath(target)
    for source in inputs:
        if source is not None and _contains(real, os.path.realpath(source)):
            raise OutputFolderError(f"{target}: the output folder would replace the input {source}")
    if os.path.lexists(real) and not os.path.isdir(real):
        raise OutputFolderError(f"{target}: exists and is not a folder; choose another output folder")
    if not os.path.isdir(real):
        return
    if force:
        protected = {os.path.realpath(os.getcwd()), os.path.realpath(os.path.expanduser("~")), os.path.realpath(os.sep)}
        if any(_contains(real, folder) for folder in protected):
            raise OutputFolderError(f"{target}: refusing to replace the current, home or root folder (or one above)")
        return
    reason = _not_replaceable(real, kind)
    if reason is not None:
        kind_name = what or f"{kind} folder"
        raise OutputFolderError(f"{target}: exists and is not {kind_name} that hairlod wrote ({reason}); "
                                f"choose another output folder, or force the replacement (--force, force=True)")


def _renameat2():
    try:
        function = ctypes.CDLL(None, use_errno=True).renameat2
    except (AttributeError, OSError):
        return None
    function.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    function.restype = ctypes.c_int
    return function


_RENAMEAT2 = _renameat2()
_AT_FDCWD, _RENAME_NOREPLACE, _RENAME_EXCHANGE = -100, 1, 2


def _rename(source, target, flags):
    """renameat2(source, target, flags); returns 0 or the errno (ENOSYS / EINVAL: not supported)."""
    if _RENAMEAT2 is None:
        return errno.ENOSYS
    if _RENAMEAT2(_AT_FDCWD, os.fsencode(source), _AT_FDCWD, os.fsencode(target), flags) == 0:
        return 0
    return ctypes.get_errno()


def _install(staging, target, recheck):
    """Moves the finished folder `staging` to `target`, replacing an existing one in one step.
    `recheck()` runs again before replacing a folder that appeared meanwhile."""
    for _ in range(100):
        failure = _rename(staging, target, _RENAME_NOREPLACE)
        if failure == 0:
            return
        if failure in (errno.EEXIST, errno.ENOTEMPTY):
            recheck()
            failure = _rename(staging, target, _RENAME_EXCHANGE)
            if failure == 0:
                return  # staging now holds the old folder; the caller removes it
            if failure == errno.ENOENT:
                continue  # another writer moved it away: try again
        if failure not in (errno.ENOSYS, errno.EINVAL):
            raise OSError(failure, f"cannot move the finished folder into place: {os.strerror(failure)}", target)
        break
    # Without renameat2: move the old folder aside (a temporary name), move the new one in.
    retired = temporary_path(target)
    if os.path.isdir(target):
        recheck()
        os.rename(target, retired)
    try:
        os.rename(staging, target)
    except BaseException:
        if os.path.isdir(retired):
            os.rename(retired, target)
        raise
    _remove(retired)


def replace_folder(target, kind, write, force=False, inputs=(), what=None):
    """Builds folder `target` by calling write(staging) on an empty temporary folder, then moves it
    into place atomically. An existing `target` is replaced only when it is a folder of `kind`
    (manifest "format" prefix, e.g. "hairlod-lod/") holding only the files its manifest names, or
    with `force` (never the current, home or root folder); never a file, nor a folder holding one of
    `inputs`; `what` names the kind in messages. Refusals raise OutputFolderError before write()
    runs. Missing parent folders are made. Returns write()'s result."""
    target = os.path.abspath(os.fspath(target))
    parent = os.path.dirname(target)
    check_folder_target(target, kind, force, inputs, what)
    os.makedirs(parent, exist_ok=True)
    begin_writing(target)
    staging = temporary_path(target)
    with _installing:
        os.mkdir(staging)  # 0777 less the umask, as for any folder the user makes
    try:
        try:
            result = write(staging)
        except ValueError as error:
            # Name the user's folder, not the temporary one the file was written into.
            raise ValueError(str(error).replace(staging, target)) from None
        with _installing:
            _install(staging, target, lambda: check_folder_target(target, kind, force, inputs, what))
            completed(target)
            _remove(staging)  # the replaced folder, after an exchange
    finally:
        with _installing:
            _remove(staging)
    return result
