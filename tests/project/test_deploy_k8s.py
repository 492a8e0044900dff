"""deploy/: the zero-to-jupyterhub values file and the project's image (issue 26).

No cluster here: the values must parse, name only keys the chart really has (its
``values.schema.yaml`` says ``additionalProperties: false`` almost everywhere, so Helm refuses an
unknown key), pass JupyterHub's own traitlets under ``hub.config`` that exist, open on the
dashboard, and ask for resources that hold what the README's sizing table measured.  The image's
entry point is run for real (it prepares a student's class and home, then execs its arguments).
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
DEPLOY = ROOT / "deploy"

#: Key paths of the JupyterHub Helm chart used by deploy/*.yaml, each checked against the chart's
#: ``jupyterhub/values.schema.yaml`` (zero-to-jupyterhub-k8s, commit 48ea50e3, chart appVersion 5.5.0).
#: Below ``hub.config`` the chart passes traitlets configuration through (checked against JupyterHub
#: itself below); below ``singleuser.extraEnv`` any variable name goes.
CHART_KEYS = frozenset(
    {
        "hub",
        "hub.config",
        "singleuser",
        "singleuser.image",
        "singleuser.image.name",
        "singleuser.image.tag",
        "singleuser.image.pullPolicy",
        "singleuser.defaultUrl",
        "singleuser.extraEnv",
        "singleuser.cpu",
        "singleuser.cpu.limit",
        "singleuser.cpu.guarantee",
        "singleuser.memory",
        "singleuser.memory.limit",
        "singleuser.memory.guarantee",
        "singleuser.startTimeout",
        "singleuser.storage",
        "singleuser.storage.capacity",
        "cull",
        "cull.enabled",
        "cull.timeout",
        "cull.every",
        "cull.maxAge",
        "cull.users",
        "scheduling",
        "scheduling.userScheduler",
        "scheduling.userScheduler.enabled",
        "prePuller",
        "prePuller.hook",
        "prePuller.hook.enabled",
    }
)
PASS_THROUGH = ("hub.config.", "singleuser.extraEnv.")
MIB = {"K": 1e3 / 2**20, "M": 1e6 / 2**20, "G": 1e9 / 2**20, "Ki": 1 / 1024, "Mi": 1.0, "Gi": 1024.0}


def _paths(node: Any, prefix: str = "") -> list[str]:
    out = []
    if isinstance(node, dict):
        for key, value in node.items():
            path = f"{prefix}{key}"
            out.append(path)
            if not path.startswith(PASS_THROUGH) and not any(path + "." == p for p in PASS_THROUGH):
                out += _paths(value, path + ".")
    return out


def _values() -> dict[str, Any]:
    return yaml.safe_load((DEPLOY / "values.yaml").read_text(encoding="utf-8"))


def _mib(quantity: str | int | float) -> float:
    """A Kubernetes memory quantity (``768M``, ``1Gi``, bytes) in MiB."""
    m = re.fullmatch(r"([0-9.]+)([KMG]i?)?", str(quantity))
    assert m, f"not a memory quantity: {quantity!r}"
    return float(m.group(1)) * MIB[m.group(2)] if m.group(2) else float(m.group(1)) / 2**20


def measured_per_student() -> dict[str, tuple[float, float]]:
    """The README's measured rows: label -> (CPU in cores, memory in MiB)."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| (kernel \+ its chair|Jupyter server) [^|]*\| ([0-9.]+) \| ([0-9.]+) \|", text, re.M)
    return {label: (float(cpu), float(mib)) for label, cpu, mib in rows}


def test_every_deploy_yaml_parses_and_names_only_chart_keys() -> None:
    files = sorted(DEPLOY.glob("*.yaml"))
    assert files, "deploy/ has no values file"
    for path in files:
        values = yaml.safe_load(path.read_text(encoding="utf-8"))
        assert isinstance(values, dict), path
        unknown = [p for p in _paths(values) if p not in CHART_KEYS and not p.startswith(PASS_THROUGH)]
        assert not unknown, f"{path.name}: keys the chart does not have: {unknown}"


@pytest.mark.slow
def test_hub_config_names_real_jupyterhub_traits() -> None:
    from jupyterhub.app import JupyterHub
    from jupyterhub.auth import Authenticator
    from jupyterhub.authenticators.shared import SharedPasswordAuthenticator
    from jupyterhub.spawner import Spawner

    # KubeSpawner is not installed here: the traits set on it must be the base Spawner's
    classes = {
        "JupyterHub": JupyterHub,
        "Authenticator": Authenticator,
        "SharedPasswordAuthenticator": SharedPasswordAuthenticator,
        "KubeSpawner": Spawner,
    }
    config = _values()["hub"]["config"]
    for name, traits in config.items():
        assert name in classes, f"hub.config.{name}: not a class checked here"
        missing = set(traits) - set(classes[name].class_trait_names(config=True))
        assert not missing, f"hub.config.{name}: no such traits {missing}"
    assert config["JupyterHub"]["authenticator_class"] == "shared-password"  # as `pmk hub`
    from importlib.metadata import entry_points

    assert "shared-password" in {e.name for e in entry_points(group="jupyterhub.authenticators")}


def test_single_user_servers_open_the_dashboard_with_kubespawner_defaults() -> None:
    from pmk_nb.serve.hub_config import DASHBOARD_URL, KERNEL_IDLE

    single = _values()["singleuser"]
    assert single["defaultUrl"] == DASHBOARD_URL
    assert single["image"]["name"] and single["image"]["tag"]
    args = _values()["hub"]["config"]["KubeSpawner"]["args"]
    assert f"--MappingKernelManager.cull_idle_timeout={KERNEL_IDLE}" in args
    assert _values()["cull"]["enabled"] is True


def test_limits_hold_what_the_sizing_table_measured() -> None:
    measured = measured_per_student()
    assert set(measured) == {"kernel + its chair", "Jupyter server"}, measured
    (kernel_cpu, kernel_mib), (server_cpu, server_mib) = measured["kernel + its chair"], measured["Jupyter server"]
    single = _values()["singleuser"]
    chairs = int(single["extraEnv"]["PMK_MAX_CHAIRS"])
    guarantee, limit = _mib(single["memory"]["guarantee"]), _mib(single["memory"]["limit"])
    assert guarantee >= server_mib + kernel_mib, "the guarantee must hold a student's server and one page"
    assert limit >= server_mib + chairs * kernel_mib, "the limit must hold every chair a student may open"
    assert float(single["cpu"]["guarantee"]) >= server_cpu + kernel_cpu
    assert float(single["cpu"]["limit"]) >= chairs * kernel_cpu + server_cpu


@pytest.mark.slow
def test_the_image_entry_point_prepares_the_class_and_runs_its_arguments(tmp_path: Path) -> None:
    dockerfile = (DEPLOY / "Dockerfile").read_text(encoding="utf-8")
    assert 'ENTRYPOINT ["/usr/local/bin/pmk-class-start"]' in dockerfile
    assert "COPY --chown=root:root deploy/pmk-class-start.py /usr/local/bin/pmk-class-start" in dockerfile
    probe = "import json, os; print(json.dumps({k: os.environ.get(k) for k in ('PMK_CLASSROOM', 'PMK_CONFIG_DIR')}))"
    env = {**os.environ, "HOME": str(tmp_path), "PMK_MAX_CHAIRS": "3", "PYTHONPATH": str(ROOT)}
    out = subprocess.run(
        [sys.executable, str(DEPLOY / "pmk-class-start.py"), sys.executable, "-c", probe],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
        check=True,
    )
    seen = json.loads(out.stdout.strip().splitlines()[-1])
    settings = json.loads(Path(seen["PMK_CLASSROOM"]).read_text(encoding="utf-8"))
    assert settings["max_chairs"] == 3
    assert Path(settings["map_yaml"]).is_file()
    assert seen["PMK_CONFIG_DIR"] == str(tmp_path / ".pmk")
    assert (tmp_path / "dashboard.ipynb").is_file()


@pytest.mark.parametrize("quantity,mib", [("768M", 732.4), ("1Gi", 1024.0), ("320M", 305.2)])
def test_memory_quantities(quantity: str, mib: float) -> None:
    assert _mib(quantity) == pytest.approx(mib, abs=0.1)
