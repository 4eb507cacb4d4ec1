"""Generate the Python UMAA types from the IDL in ``idl/``: built, never committed (git ignores them).

Three packages, each a top-level package in ``backend/`` (cyclonedds imports a member's type by the module path
in its annotation, so the package name is in the generated code):

- ``UMAA``: UMAA 3.0.1 (``idl/UMAA``), every struct final (idlc's ``-x final``), the console's own types;
- ``UMAA_appendable``: the same types appendable, what an RTI Connext 3.0.1 vehicle writes;
- ``UMAA_6_0``: UMAA 6.0 (``idl/umaa-6.0/UMAA``), final;
- ``UMAA_6_0_appendable``: the 6.0 types appendable, what a vehicle on RTI's UMAA kit writes.

Each keeps UMAA's wire type names (``UMAA::...``); only the Python package differs, so all load in one process.
``scripts/setup.sh`` and the Docker images run ``python -m sem_console.idlgen`` before installing the backend; it
regenerates only when ``idl/`` or this file changed since the last run (a stamp in ``backend/``). The test suite
regenerates into a temporary folder and fails when the built code differs, or when a generated file is in git.

Why this is not a plain ``idlc -l py`` call:

1. The ``idlc`` shipped in the cyclonedds 11.0.1 wheel segfaults before
   ``main`` (cyclonedds-python issue #336). The cause is in the ELF file, not
   in idlc: the wheel's patchelf step moved ``.dynamic`` so that it spills
   out of the writable LOAD segment into a read-only page, and the dynamic
   loader faults when it stores its debugger hook into the ``DT_DEBUG``
   entry. We copy the binary into a cache folder and retag that one entry
   as ``DT_BIND_NOW`` (which asks only for eager symbol binding); nothing
   else changes, so it is the same idlc and the same ``_idlpy`` backend that
   the runtime ships with, and the output matches the runtime exactly.
   Building Cyclone from source is not possible here (no network beyond the
   package registries) and an idlc from another Cyclone release would not
   match the 11.0.1 Python runtime.
2. UMAA puts every enum in a module of its own name
   (``...::CommandStatusEnumType::CommandStatusEnumType``). Cyclone's idlc
   enforces the IDL rule that a module's name may not be declared again
   inside it, so it rejects that IDL. ``idl/`` keeps UMAA's layout; idlc is
   fed a copy in which such enums carry a temporary suffix, and the suffix is
   removed from the generated Python. Enum type names never reach the wire
   for matching (XTypes minimal type objects hold literal name hashes only);
   the restored names keep the complete type information right as well.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import re
import shutil
import struct
import subprocess
import sys
import sysconfig
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
IDL_DIR = REPO / "idl"
IDL_6_0 = IDL_DIR / "umaa-6.0"
OUT_DIR = REPO / "backend"
SUFFIX = "__UMAA_SAME_NAME"

DT_DEBUG = 21
DT_BIND_NOW = 24
PT_DYNAMIC = 2


def _wheel_paths() -> tuple[Path, Path, Path]:
    import cyclonedds

    pkg = Path(cyclonedds.__file__).resolve().parent
    idlc = pkg / ".libs" / "idlc"
    libs = pkg.parent / "cyclonedds.libs"
    plugin = next(pkg.glob("_idlpy*"))
    return idlc, libs, plugin


def patch_dt_debug(src: Path, dst: Path) -> None:
    """Copy an x86-64 ELF executable, retagging its DT_DEBUG entry as DT_BIND_NOW."""
    data = bytearray(src.read_bytes())
    if data[:4] != b"\x7fELF" or data[4] != 2 or data[5] != 1:
        raise RuntimeError(f"{src} is not a 64-bit little-endian ELF file")
    phoff = struct.unpack_from("<Q", data, 0x20)[0]
    phentsize, phnum = struct.unpack_from("<HH", data, 0x36)
    for i in range(phnum):
        p_type, _flags, offset, _va, _pa, filesz = struct.unpack_from("<IIQQQQ", data, phoff + i * phentsize)
        if p_type != PT_DYNAMIC:
            continue
        for entry in range(offset, offset + filesz, 16):
            if struct.unpack_from("<q", data, entry)[0] == DT_DEBUG:
                struct.pack_into("<q", data, entry, DT_BIND_NOW)
    dst.write_bytes(bytes(data))
    dst.chmod(0o755)


def working_idlc(cache: Path) -> Path:
    idlc, _libs, _plugin = _wheel_paths()
    cache.mkdir(parents=True, exist_ok=True)
    fixed = cache / "idlc"
    if not fixed.exists() or fixed.stat().st_mtime < idlc.stat().st_mtime:
        patch_dt_debug(idlc, fixed)
    return fixed


def _rename_same_name_enums(src: Path, dst: Path) -> None:
    """Copy ``src`` IDL tree to ``dst`` with module-named enums suffixed for idlc."""
    shutil.copytree(src, dst)
    enum_decl = re.compile(r"module (\w+) \{\s*(?://[^\n]*\n\s*)*enum \1 \{")  # comments may come between
    names: set[str] = set()
    files = sorted(dst.rglob("*.idl"))
    for f in files:
        names.update(m.group(1) for m in enum_decl.finditer(f.read_text()))
    for f in files:
        text = f.read_text()
        for n in names:
            text = re.sub(rf"\benum {n} \{{", f"enum {n}{SUFFIX} {{", text)
            text = re.sub(rf"::{n}::{n}\b", f"::{n}::{n}{SUFFIX}", text)
        f.write_text(text)


def generate(
    out_dir: Path, cache: Path | None = None, idl_dir: Path = IDL_DIR, extensibility: str | None = "final"
) -> list[Path]:
    """Generate the ``UMAA`` package from the IDL files under ``idl_dir`` into ``out_dir``; return the
    written files. ``extensibility``: idlc's default for types that do not say (None: idlc's own)."""
    cache = cache or Path(tempfile.gettempdir()) / "sem-console-idlc"
    idlc = working_idlc(cache)
    _orig, libs, plugin = _wheel_paths()
    env = dict(os.environ)
    env["LD_LIBRARY_PATH"] = os.pathsep.join(filter(None, [str(libs), env.get("LD_LIBRARY_PATH")]))
    # idlc asks `python -m cyclonedds.__idlc__` where the backend is; give it this interpreter.
    env["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), sysconfig.get_path("scripts"), env.get("PATH", "")])
    with tempfile.TemporaryDirectory() as tmp:
        work_idl = Path(tmp) / "idl"
        gen = Path(tmp) / "gen"
        gen.mkdir()
        _rename_same_name_enums(idl_dir, work_idl)
        default = ["-x", extensibility] if extensibility else []
        for f in sorted(work_idl.rglob("*.idl")):
            if IDL_6_0.name in f.relative_to(work_idl).parts:
                continue  # idl/ holds 3.0.1 and, in its own folder, 6.0: each version is generated on its own
            # The Python backend writes into the current directory (it ignores -o).
            subprocess.run(
                [str(idlc), "-l", str(plugin), *default, "-I", str(work_idl), str(f)],
                cwd=gen,
                env=env,
                check=True,
                capture_output=True,
                text=True,
            )
        target = out_dir / "UMAA"
        if target.exists():
            shutil.rmtree(target)
        written = []
        for f in sorted(gen.rglob("*.py")):
            dest = target / f.relative_to(gen / "UMAA")
            dest.parent.mkdir(parents=True, exist_ok=True)
            dest.write_text(f.read_text().replace(SUFFIX, ""))
            written.append(dest)
        return written


APPENDABLE = "UMAA_appendable"
UMAA_6_0 = "UMAA_6_0"
APPENDABLE_6_0 = "UMAA_6_0_appendable"
PACKAGES = ("UMAA", APPENDABLE, UMAA_6_0, APPENDABLE_6_0)


def generate_as(
    package: str, out_dir: Path, cache: Path | None = None, idl_dir: Path = IDL_DIR, extensibility: str = "final"
) -> list[Path]:
    """The types of ``idl_dir`` as the package ``package`` in ``out_dir``: the wire type names stay ``UMAA::...``
    (each class's ``typename``); cyclonedds imports a member's type by the module path in its annotation, so those
    name ``package``."""
    with tempfile.TemporaryDirectory() as tmp:
        written = generate(Path(tmp), cache, idl_dir, extensibility=extensibility)
        target = out_dir / package
        if target.exists():
            shutil.rmtree(target)
        out = []
        for f in written:
            dest = target / f.relative_to(Path(tmp) / "UMAA")
            dest.parent.mkdir(parents=True, exist_ok=True)
            # the `typename` arguments (double-quoted) and the typedefs' names, the names on the wire, keep UMAA's
            text = f.read_text().replace("'UMAA.", f"'{package}.").replace("import UMAA", f"import {package}")
            text = text.replace(f"types.typedef['{package}.", "types.typedef['UMAA.")
            backend = "Generated by Eclipse Cyclone DDS idlc Python Backend"
            dest.write_text(text.replace(backend, f"{backend} (as {package}: sem_console.idlgen)"))
            out.append(dest)
        return out


def generate_appendable(out_dir: Path, cache: Path | None = None, idl_dir: Path = IDL_DIR) -> list[Path]:
    """The 3.0.1 types with every struct appendable, as the package ``UMAA_appendable`` in ``out_dir``: the copies the
    console reads GPSReport and GPSFixReport with from an RTI Connext vehicle, whose types are appendable (RTI's
    default for IDL that does not say; docs/dds.md, "One reader per extensibility")."""
    return generate_as(APPENDABLE, out_dir, cache, idl_dir, extensibility="appendable")


def generate_6_0(out_dir: Path, cache: Path | None = None, idl_dir: Path = IDL_6_0) -> list[Path]:
    """The UMAA 6.0 types (final), as the package ``UMAA_6_0`` in ``out_dir``."""
    return generate_as(UMAA_6_0, out_dir, cache, idl_dir)


def generate_6_0_appendable(out_dir: Path, cache: Path | None = None, idl_dir: Path = IDL_6_0) -> list[Path]:
    """The UMAA 6.0 types with every struct appendable, as the package ``UMAA_6_0_appendable`` in ``out_dir``: the
    copies the console reads GlobalPoseReportType with from a vehicle on RTI's UMAA kit (XCDR2, RTI's types
    appendable; docs/umaa-versions.md, "RTI Connext")."""
    return generate_as(APPENDABLE_6_0, out_dir, cache, idl_dir, extensibility="appendable")


def generate_all(out_dir: Path, cache: Path | None = None) -> dict[str, list[Path]]:
    """Every generated package in ``out_dir``, by package name."""
    return {
        "UMAA": generate(out_dir, cache),
        APPENDABLE: generate_appendable(out_dir, cache),
        UMAA_6_0: generate_6_0(out_dir, cache),
        APPENDABLE_6_0: generate_6_0_appendable(out_dir, cache),
    }


def inputs_digest() -> str:
    """What the generated code follows from: every IDL file (path and text), this file and the idlc plug-in's name."""
    h = hashlib.sha256()
    for f in sorted(IDL_DIR.rglob("*.idl")):
        h.update(str(f.relative_to(IDL_DIR)).encode() + b"\0" + f.read_bytes() + b"\0")
    h.update(Path(__file__).read_bytes())
    h.update(_wheel_paths()[2].name.encode())
    return h.hexdigest()


STAMP = ".idlgen-stamp"


def up_to_date(out_dir: Path) -> bool:
    stamp = out_dir / STAMP
    return (
        stamp.exists() and stamp.read_text() == inputs_digest() and all((out_dir / p / "__init__.py").exists() for p in PACKAGES)
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Generate Python types from idl/ with Cyclone DDS idlc.")
    parser.add_argument("--out", type=Path, default=OUT_DIR, help="folder to write the packages into (default: backend/)")
    parser.add_argument(
        "--if-stale", action="store_true", help="only when idl/ or idlgen changed since the last run into the same folder"
    )
    args = parser.parse_args(argv)
    if args.if_stale and up_to_date(args.out):
        return 0
    try:
        written = generate_all(args.out)
    except subprocess.CalledProcessError as e:
        print(f"idlc failed on {e.cmd[-1]}:\n{e.stderr}", file=sys.stderr)
        return 1
    (args.out / STAMP).write_text(inputs_digest())
    print("wrote " + ", ".join(f"{len(files)} files under {args.out / name}" for name, files in written.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
