"""An unusable FLEXKANE_CACHE_DIR (a file, a directory that cannot be created, a read-only one) gives a
warning naming the path and a temporary cache, never a traceback; derivations and compiled modules
still work."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

import flexkane
from flexkane.derivation_cache import cache_path, cached_derive
from flexkane.numerics import build_module, generate_rhs_source, structure_key
from flexkane.numerics import jit_module


def _unusable(kind: str, tmp_path: Path) -> tuple[Path, str]:
    """A cache path of the given kind and the reason the warning gives."""
    if kind == "file":
        path = tmp_path / "cache-file"
        path.write_text("not a directory")
        return path, "it is a file, not a directory"
    if kind == "uncreatable":
        blocker = tmp_path / "blocker"
        blocker.write_text("")
        return blocker / "cache", "it cannot be created"
    if os.geteuid() == 0:           # root writes through permission bits: use a read-only file system
        return Path("/proc"), "it is not writable"
    path = tmp_path / "read-only"
    path.mkdir()
    path.chmod(0o555)
    return path, "it is not writable"


@pytest.fixture(autouse=True)
def _fresh_fallbacks(monkeypatch):
    monkeypatch.setattr(jit_module, "_fallback", {})


@pytest.mark.parametrize("kind", ["file", "uncreatable", "read-only"])
def test_an_unusable_cache_dir_falls_back_to_a_temporary_one_with_a_warning(kind, tmp_path, monkeypatch,
                                                                             capsys, models):
    path, reason = _unusable(kind, tmp_path)
    monkeypatch.setenv("FLEXKANE_CACHE_DIR", str(path))
    root = jit_module.usable_cache_dir()
    err = capsys.readouterr().err
    assert root != path and root.is_dir() and os.access(root, os.W_OK)
    assert f"cache directory {path} (FLEXKANE_CACHE_DIR) is unusable: {reason}" in err
    assert jit_module.usable_cache_dir() == root and capsys.readouterr().err == ""   # warned once
    source = generate_rhs_source(models.pendulum())
    key = structure_key(source, "unusable-cache", kind)
    module = build_module(source, key)
    assert Path(module.__file__).parent.parent == root
    eom = cached_derive(flexkane.builtin_model("falling-beam"))
    assert cache_path(eom.model).parent.parent == root and cache_path(eom.model).is_file()


def test_a_usable_cache_dir_is_created_and_used_silently(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("FLEXKANE_CACHE_DIR", str(tmp_path / "new" / "cache"))
    assert jit_module.usable_cache_dir() == tmp_path / "new" / "cache"
    assert (tmp_path / "new" / "cache").is_dir() and capsys.readouterr().err == ""


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["file", "uncreatable", "read-only"])
def test_run_with_an_unusable_cache_dir_warns_and_completes(kind, tmp_path):
    path, reason = _unusable(kind, tmp_path)
    model = Path(__file__).parents[1] / "validation" / "models" / "torque-pendulum.toml"
    process = subprocess.run([sys.executable, "-m", "flexkane", "run", str(model), "--t-end", "0.1",
                              "--out", str(tmp_path / "out"), "--quiet"], capture_output=True, text=True,
                             env=dict(os.environ, FLEXKANE_CACHE_DIR=str(path)), timeout=600)
    assert process.returncode == 0, process.stderr
    assert "Traceback" not in process.stderr and f"cache directory {path}" in process.stderr
    assert reason in process.stderr
    assert flexkane.load_results(tmp_path / "out").t[-1] == 0.1
