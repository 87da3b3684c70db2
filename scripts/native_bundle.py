"""Makes a compiled extension module self-contained, the way auditwheel repairs a wheel: every shared
library it loads, except the C/C++ runtime, is copied beside it under a name of its own
(lib<name>-hairlod-<hash>.so...), with that name as its soname, its dependants pointing at the copy
and $ORIGIN run paths, so that nothing else on the system is needed and nothing collides with the
copies of TBB, Embree, OpenSubdiv or OpenEXR that Blender itself has loaded. (Symbols are a second
matter: the core calls Embree through pointers looked up in its own libraries, render/embree.h.)

Needs ldd (glibc) and patchelf (Debian package patchelf), run where the module was built."""

import hashlib
import os
import re
import shutil
import subprocess

# The runtime every Linux system (and every Blender) has: glibc's libraries and GCC's C++ runtime.
RUNTIME = re.compile(r"^(linux-vdso|ld-linux[-\w]*|libc|libm|libdl|libpthread|librt|libresolv|libutil|"
                     r"libstdc\+\+|libgcc_s)\.so")


class BundleError(Exception):
    pass


def _run(*command):
    try:
        return subprocess.run(command, check=True, capture_output=True, text=True).stdout
    except FileNotFoundError:
        raise BundleError(f"{command[0]} not found (apt-get install {'patchelf' if command[0] == 'patchelf' else 'libc-bin'})") from None
    except subprocess.CalledProcessError as error:
        raise BundleError(f"{' '.join(command)} failed: {error.stderr.strip()}") from None


def needed(path):
    """The DT_NEEDED names of a shared object."""
    return _run("patchelf", "--print-needed", path).split()


def dependencies(path):
    """{soname: resolved path} of every library `path` loads (the whole closure, as ldd resolves it),
    the runtime left out."""
    found = {}
    for line in _run("ldd", path).splitlines():
        match = re.match(r"\s*(\S+) => (\S+)", line)
        if match is None:
            continue
        name, resolved = match.groups()
        if resolved == "not":
            raise BundleError(f"{path}: {name} is not found on this system")
        if not RUNTIME.match(name):
            found[name] = resolved
    return found


def bundled_name(soname, path):
    """libtbb.so.12 -> libtbb-hairlod-1a2b3c4d.so.12: a name no other copy of the library has."""
    with open(path, "rb") as library:
        digest = hashlib.sha256(library.read()).hexdigest()[:8]
    stem, dot, version = soname.partition(".so")
    return f"{stem}-hairlod-{digest}{dot}{version}"


def bundle(module, libs_dir):
    """Copies the libraries `module` (a built extension, patched in place) loads into `libs_dir` and
    points everything at the copies. Returns {original soname: bundled file name}."""
    libraries = dependencies(module)
    renamed = {soname: bundled_name(soname, path) for soname, path in libraries.items()}
    os.makedirs(libs_dir, exist_ok=True)
    for soname, path in libraries.items():
        copy = os.path.join(libs_dir, renamed[soname])
        shutil.copyfile(path, copy)
        os.chmod(copy, 0o755)
        _run("patchelf", "--set-soname", renamed[soname], copy)
        _point_at_copies(copy, renamed, "$ORIGIN")
    relative = os.path.relpath(libs_dir, os.path.dirname(module))
    _point_at_copies(module, renamed, "$ORIGIN" if relative == "." else f"$ORIGIN/{relative}")
    return renamed


def _point_at_copies(path, renamed, run_path):
    replacements = []
    for name in needed(path):
        if name in renamed:
            replacements += ["--replace-needed", name, renamed[name]]
    if replacements:
        _run("patchelf", *replacements, path)
    _run("patchelf", "--remove-rpath", path)
    _run("patchelf", "--set-rpath", run_path, path)


def check_self_contained(module, libs_dir):
    """Raises BundleError unless every library `module` and its bundled copies need is either in
    `libs_dir` or part of the runtime."""
    present = set(os.listdir(libs_dir))
    for path in [module] + [os.path.join(libs_dir, name) for name in sorted(present)]:
        for name in needed(path):
            if not RUNTIME.match(name) and name not in present:
                raise BundleError(f"{os.path.basename(path)} needs {name}, which is neither bundled nor runtime")
