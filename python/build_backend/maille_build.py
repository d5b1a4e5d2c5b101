"""PEP 517 build backend for `pip install .`: the engine's CMake build of the Python module,
packed into a wheel with the standard library alone (pip needs nothing from the network).

The wheel holds the package directory CMake makes (<build>/python/maille: __init__.py, _maille,
_cores), built for the interpreter that runs pip. Environment:
  MAILLE_BUILD_DIR   a CMake build directory to build the module in (configured already, or
                     configured here); default: build/pip in the source tree, Release, for any
                     x86-64 CPU (MAILLE_ARCH=portable; MAILLE_ARCH=native in the environment
                     builds for this one)
  MAILLE_JOBS        parallel compile jobs (default: the CPU count)
"""
import base64
import hashlib
import os
import re
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

_SOURCE = Path(__file__).resolve().parents[2]


def _version():
    text = (_SOURCE / "CMakeLists.txt").read_text()
    m = re.search(r"project\(maille VERSION ([0-9.]+)", text)
    if not m:
        raise RuntimeError("CMakeLists.txt: no `project(maille VERSION ...)` line")
    return m.group(1)


def _tag():
    impl = "cp%d%d" % sys.version_info[:2]
    platform = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    return "%s-%s-%s" % (impl, impl, platform)


def _run(cmd):
    print("maille_build: " + " ".join(str(c) for c in cmd), flush=True)
    # pip runs this backend in an isolated environment whose PYTHONPATH hides the site-packages;
    # CMake's interpreter must see its own (NumPy's headers are found through it).
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONNOUSERSITE")}
    subprocess.run([str(c) for c in cmd], check=True, env=env)


def _interpreter():
    """The interpreter the module is built for: the running one, or, in a virtual environment,
    its base interpreter (the same ABI; a venv made with --system-site-packages sees its NumPy)."""
    base = getattr(sys, "_base_executable", None)
    if sys.prefix != sys.base_prefix and base and Path(base).exists():
        return str(Path(base).resolve())
    return sys.executable


def _build_module():
    """Configures (when needed) and builds the module; returns the package directory."""
    build = Path(os.environ.get("MAILLE_BUILD_DIR") or _SOURCE / "build" / "pip").resolve()
    if not (build / "CMakeCache.txt").exists():
        generator = ["-G", "Ninja"] if subprocess.run(
            ["ninja", "--version"], capture_output=True).returncode == 0 else []
        _run(["cmake", "-S", _SOURCE, "-B", build, *generator,
              "-DCMAKE_BUILD_TYPE=Release",
              "-DMAILLE_ARCH=" + os.environ.get("MAILLE_ARCH", "portable"),
              "-DMAILLE_BUILD_TESTS=OFF", "-DMAILLE_BUILD_BENCH=OFF",
              "-DMAILLE_BUILD_PYTHON=ON", "-DPython3_EXECUTABLE=" + _interpreter(),
              "-DPYTHON_EXECUTABLE=" + _interpreter()])
    jobs = os.environ.get("MAILLE_JOBS") or str(os.cpu_count() or 1)
    _run(["cmake", "--build", build, "--parallel", jobs,
          "--target", "maille_python", "maille_python_cores"])
    package = build / "python" / "maille"
    found = [p for p in package.glob("_maille*.so")]
    if not found:
        raise RuntimeError(
            "%s: the module was not built (pybind11-dev, python3-dev and python3-numpy are "
            "needed: scripts/setup.sh installs them)" % package)
    return package


def _record_line(name, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return "%s,sha256=%s,%d" % (name, digest, len(data))


def _metadata(version):
    return ("Metadata-Version: 2.1\nName: maille\nVersion: %s\n"
            "Summary: Mass-interaction (mass-spring) physics: cloth, ropes, nets, lattices, sound\n"
            "Requires-Python: >=3.9\nRequires-Dist: numpy\n" % version)


def get_requires_for_build_wheel(config_settings=None):
    return []


def get_requires_for_build_sdist(config_settings=None):
    return []


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    version = _version()
    info = Path(metadata_directory) / ("maille-%s.dist-info" % version)
    info.mkdir(parents=True, exist_ok=True)
    (info / "METADATA").write_text(_metadata(version))
    return info.name


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    version = _version()
    package = _build_module()
    tag = _tag()
    name = "maille-%s-%s.whl" % (version, tag)
    info = "maille-%s.dist-info" % version
    files = {}
    for path in sorted(package.iterdir()):
        if path.is_file() and (path.suffix in (".py", ".so")):
            files["maille/" + path.name] = path.read_bytes()
    files[info + "/METADATA"] = _metadata(version).encode()
    files[info + "/WHEEL"] = ("Wheel-Version: 1.0\nGenerator: maille_build\n"
                              "Root-Is-Purelib: false\nTag: %s\n" % tag).encode()
    record = [_record_line(n, d) for n, d in files.items()] + [info + "/RECORD,,"]
    files[info + "/RECORD"] = ("\n".join(record) + "\n").encode()
    out = Path(wheel_directory) / name
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        for n, d in files.items():
            entry = zipfile.ZipInfo(n, date_time=(2020, 1, 1, 0, 0, 0))
            entry.external_attr = (0o755 if n.endswith(".so") else 0o644) << 16
            z.writestr(entry, d, zipfile.ZIP_DEFLATED)
    return name


def build_sdist(sdist_directory, config_settings=None):
    raise RuntimeError("maille_build: no source distribution: install from the source tree "
                       "(`pip install .`) or build with CMake (README.md)")
