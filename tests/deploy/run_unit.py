#!/usr/bin/env python3
"""Runs an installed systemd unit's command lines the way systemd would, from a throw-away root.

usage: run_unit.py ROOT UNIT [--instance I] [--pre-log FILE]

Reads ROOT/usr/lib/systemd/system/UNIT ([Service] EnvironmentFile=, ExecStartPre=, ExecStart=),
loads the environment files from ROOT, substitutes %i, expands ${VAR} (one argument) and $VAR
(split at white space) as systemd.service(5) says, maps /usr/... and /etc/hullpose/... arguments
into ROOT, runs every ExecStartPre (its output and exit status go to --pre-log; the start-up
checks judge this machine, not the rig under test) and then execs ExecStart. Only what hullpose's
units use is supported; anything else is an error, so a unit that grows a feature fails here first.
"""
import os
import re
import shlex
import subprocess
import sys


def parse_unit(path):
    service, section = {}, None
    for raw in open(path):
        line = raw.strip()
        if not line or line[0] in "#;":
            continue
        if line.startswith("["):
            section = line
            continue
        key, _, value = line.partition("=")
        if section == "[Service]":
            service.setdefault(key.strip(), []).append(value.strip())
    return service


def load_env(root, spec, env):
    optional = spec.startswith("-")
    path = root + spec.lstrip("-")
    if not os.path.exists(path):
        if optional:
            return
        sys.exit(f"run_unit: EnvironmentFile {spec} missing under {root}")
    for raw in open(path):
        line = raw.strip()
        if not line or line[0] in "#;":
            continue
        key, _, value = line.partition("=")
        value = value.strip()
        if len(value) >= 2 and value[0] == value[-1] and value[0] in "\"'":
            value = value[1:-1]
        env[key.strip()] = value


def expand(command, env, instance, root):
    command = command.replace("%i", instance)
    if command[:1] in "-+!@:":
        sys.exit(f"run_unit: command prefix '{command[0]}' not supported: {command}")
    args = []
    for word in shlex.split(command):
        whole = re.fullmatch(r"\$([A-Za-z_][A-Za-z0-9_]*)", word)
        if whole:  # $VAR: split into words, nothing when empty
            args.extend(env.get(whole.group(1), "").split())
            continue
        word = re.sub(r"\$\{([A-Za-z_][A-Za-z0-9_]*)\}", lambda m: env.get(m.group(1), ""), word)
        if word.startswith("/usr/") or word.startswith("/etc/hullpose"):
            word = root + word
        args.append(word)
    return args


def main():
    root, unit = os.path.abspath(sys.argv[1]), sys.argv[2]
    instance, pre_log = "", os.devnull
    rest = sys.argv[3:]
    while rest:
        opt, value, rest = rest[0], rest[1], rest[2:]
        if opt == "--instance":
            instance = value
        elif opt == "--pre-log":
            pre_log = value
        else:
            sys.exit(f"run_unit: unknown option {opt}")
    service = parse_unit(f"{root}/usr/lib/systemd/system/{unit}")
    env = dict(os.environ)
    for spec in service.get("EnvironmentFile", []):
        load_env(root, spec, env)
    with open(pre_log, "a") as log:
        for pre in service.get("ExecStartPre", []):
            args = expand(pre, env, instance, root)
            log.write("$ " + " ".join(args) + "\n")
            log.flush()
            rc = subprocess.call(args, stdout=log, stderr=log, env=env)
            log.write(f"exit status {rc}\n")
    (start,) = service["ExecStart"]
    args = expand(start, env, instance, root)
    os.execve(args[0], args, env)


if __name__ == "__main__":
    main()
