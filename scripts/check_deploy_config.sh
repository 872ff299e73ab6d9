#!/usr/bin/env bash
# Checks the deployment files without docker or network (docs/deploy.md):
#  - docker/nginx.conf with each upstream list (single, replicated) passes `nginx -t`, on a
#    copy whose upstream host names are 127.0.0.1 (nginx -t resolves them; compose's service
#    names exist only inside compose's network);
#  - docker/compose.yaml parses, its replicated profile has postgres, the replicas and nginx,
#    every replica runs on PostgreSQL and is in both of nginx's upstream lists (any replica, a
#    track's own) and nothing else is,
#    and every file it mounts exists;
#  - docker/Dockerfile installs what the build needs: one of its stages every package that
#    scripts/setup.sh installs for the server (all but postgresql, which only the tests use), and
#    its runtime stage, for every shared library the built locus-server and locus load, the
#    package that holds it or a listed package that depends on it (when the build is there:
#    readelf and dpkg on this machine, no docker).
#  - every locus-server behind nginx (the replicas; `locus` behind the `proxy` profile's nginx)
#    names that nginx's fixed address with --trusted-proxy, so the per-client limits see each
#    phone's own address (docs/deploy.md "Per-client limits"), and nginx's address lies outside
#    the range Docker hands out.
# Needs nginx (Debian nginx-light) and python3-yaml; scripts/setup.sh installs both with
# LOCUS_DEVTOOLS=1. Takes well under a second.
set -euo pipefail
cd "$(dirname "$0")/.."

command -v nginx >/dev/null 2>&1 || { echo "check_deploy_config: nginx not found (Debian nginx-light)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

for variant in single replicated; do
  mkdir -p "$tmp/$variant"
  cp docker/nginx.conf "$tmp/$variant/nginx.conf"
  sed -E 's/^([[:space:]]*server[[:space:]]+)[A-Za-z0-9_.-]+:/\1127.0.0.1:/' \
    "docker/nginx-upstream-$variant.conf" >"$tmp/$variant/locus-upstream.conf"
  sed -i "s|/tmp/nginx|$tmp/$variant/nginx|g" "$tmp/$variant/nginx.conf"
  if ! out=$(nginx -t -q -e stderr -p "$tmp/$variant" -c "$tmp/$variant/nginx.conf" 2>&1); then
    echo "check_deploy_config: docker/nginx.conf with nginx-upstream-$variant.conf fails nginx -t:" >&2
    echo "$out" >&2
    exit 1
  fi
done

python3 - <<'PY'
import os, re, sys
import yaml

def fail(msg):
    sys.exit("check_deploy_config: docker/compose.yaml: " + msg)

with open("docker/compose.yaml") as f:
    compose = yaml.safe_load(f)
services = compose.get("services") or fail("no services")
replicated = {n: s for n, s in services.items() if "replicated" in (s.get("profiles") or [])}
for needed in ("postgres", "nginx"):
    if needed not in replicated:
        fail(f"profile replicated has no '{needed}' service")
replicas = sorted(n for n, s in replicated.items() if (s.get("entrypoint") or [""])[0] == "locus-server")
if len(replicas) < 2:
    fail(f"profile replicated has {len(replicas)} locus-server replicas, want at least 2")
for n in replicas:
    argv = replicated[n]["entrypoint"]
    db = argv[argv.index("--db") + 1] if "--db" in argv else ""
    if not db.startswith("postgresql://"):
        fail(f"replica '{n}' does not run on PostgreSQL (--db {db!r})")
    if "/health" not in " ".join(replicated[n].get("healthcheck", {}).get("test", [])):
        fail(f"replica '{n}' has no /health healthcheck")

with open("docker/nginx-upstream-replicated.conf") as f:
    blocks = re.findall(r"^upstream\s+(\w+)\s*\{(.*?)^\}", f.read(), re.M | re.S)
if sorted(name for name, _ in blocks) != ["locus", "locus_tracks"]:
    fail(f"nginx-upstream-replicated.conf defines upstreams {sorted(name for name, _ in blocks)}, want locus and locus_tracks")
for name, body in blocks:
    upstream = set(re.findall(r"^\s*server\s+([A-Za-z0-9_.-]+):", body, re.M))
    if upstream != set(replicas):
        fail(f"nginx-upstream-replicated.conf's upstream {name} lists {sorted(upstream)}, the profile's replicas are {replicas}")

def nginx_address(name):
    nets = services[name].get("networks") or {}
    addr = ((nets.get("default") or {}) if isinstance(nets, dict) else {}).get("ipv4_address")
    if not addr:
        fail(f"service '{name}' (nginx) has no fixed ipv4_address on the default network")
    return addr

def trusted(argv):
    return [argv[i + 1] for i, a in enumerate(argv) if a == "--trusted-proxy" and i + 1 < len(argv)]

import ipaddress
ipam = ((compose.get("networks") or {}).get("default") or {}).get("ipam", {}).get("config") or [{}]
dynamic = ipam[0].get("ip_range")
if not dynamic:
    fail("networks.default has no ipam ip_range: nginx's fixed address could be handed to another container")
front_of = {"nginx": replicas, "proxy": ["locus"]}
for proxy_name, behind in front_of.items():
    addr = nginx_address(proxy_name)
    if ipaddress.ip_address(addr) in ipaddress.ip_network(dynamic):
        fail(f"nginx '{proxy_name}' address {addr} is inside ip_range {dynamic}, which Docker hands out")
    for n in behind:
        argv = (services[n].get("entrypoint") or []) + (services[n].get("command") or [])
        if addr not in ",".join(trusted(argv)).split(","):
            fail(f"service '{n}' sits behind nginx '{proxy_name}' ({addr}) but does not pass --trusted-proxy {addr}")

for name, s in services.items():
    for v in s.get("volumes") or []:
        src = v.split(":")[0]
        if src.startswith("./") and not os.path.exists(os.path.join("docker", src)):
            fail(f"service '{name}' mounts {src}, which does not exist")
PY
python3 - "${LOCUS_BUILD_DIR:-build}/bin" <<'PY'
import os, re, subprocess, sys

def fail(msg):
    sys.exit("check_deploy_config: docker/Dockerfile: " + msg)

setup = open("scripts/setup.sh").read()
m = re.search(r"^packages=\(([^)]*)\)", setup, re.M) or fail("cannot find packages=(...) in scripts/setup.sh")
needed = set(m.group(1).split()) - {"postgresql"}
docker = open("docker/Dockerfile").read().replace("\\\n", " ")
stages = re.split(r"^FROM ", docker, flags=re.M)[1:]
if len(stages) != 2:
    fail(f"expected a build stage and a runtime stage, found {len(stages)}")
def installed(stage):
    pkgs = set()
    for cmd in re.findall(r"apt-get install ([^&\n]*)", stage):
        pkgs |= {w for w in cmd.split() if not w.startswith("-")}
    return pkgs
build, runtime = installed(stages[0]), installed(stages[1])
missing = sorted(needed - build - runtime)
if missing:
    fail("neither stage installs " + ", ".join(missing) + " (scripts/setup.sh does)")

bindir = sys.argv[1]
binaries = [os.path.join(bindir, b) for b in ("locus-server", "locus")]
if not all(os.path.exists(b) for b in binaries):
    print(f"check_deploy_config: no build in {bindir}: the runtime stage's libraries were not checked", file=sys.stderr)
    sys.exit(0)
base = {"libc6", "libstdc++6", "libgcc-s1"}  # in debian:12-slim
depends = set()
for p in runtime:
    out = subprocess.run(["dpkg", "-s", p], capture_output=True, text=True).stdout
    for line in out.splitlines():
        if line.startswith(("Depends:", "Pre-Depends:")):
            depends |= {d.strip().split()[0].split(":")[0] for d in line.split(":", 1)[1].replace("|", ",").split(",") if d.strip()}
for b in binaries:
    dyn = subprocess.run(["readelf", "-d", b], capture_output=True, text=True, check=True).stdout
    for lib in re.findall(r"\(NEEDED\).*\[(.+)\]", dyn):
        owner = subprocess.run(["dpkg", "-S", "*/" + lib], capture_output=True, text=True).stdout
        pkgs = {line.split(":")[0] for line in owner.splitlines() if line}
        if not pkgs:
            fail(f"{os.path.basename(b)} loads {lib}, which no installed package holds")
        if not pkgs & (runtime | base | depends):
            fail(f"{os.path.basename(b)} loads {lib} (package {', '.join(sorted(pkgs))}), which the runtime stage does not install")
PY
echo "check_deploy_config: nginx.conf (single, replicated), compose.yaml and the Dockerfile's packages ok" >&2
