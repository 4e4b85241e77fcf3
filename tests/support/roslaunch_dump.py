"""What roslaunch's own loader makes of launch files: nodes and parameters, as JSON.

Executed as a script by the Python that has roslaunch (``python3 -I roslaunch_dump.py``),
never imported by the tests: roslaunch is importable only there. The request on stdin
is a list of jobs ``{"files": [...], "args": {name: value}, "env": {...}}``; the answer
is, per job, every node of roslaunch's ``ROSLaunchConfig`` (name, namespace, package,
type, and the command line roslaunch gives its process: the args, then each remapping
as ``from:=to``) and every parameter with its value.

The loader is roslaunch's ``XmlLoader`` unchanged but for one thing: a ``<param
command=...>`` is not run (no xacro here); its value is the marker ``"<command>"``.
"""

import json
import os
import shlex
import sys

from roslaunch import xmlloader
from roslaunch.config import ROSLaunchConfig


class NoCommands(xmlloader.XmlLoader):
    def param_value(self, verbose, name, ptype, value, textfile, binfile, command):
        if command is not None:
            return "<command>"
        return super().param_value(verbose, name, ptype, value, textfile, binfile, command)


def dump(job):
    os.environ.update(job.get("env", {}))
    config = ROSLaunchConfig()
    argv = ["roslaunch"] + [f"{k}:={v}" for k, v in job.get("args", {}).items()]
    for filename in job["files"]:
        NoCommands().load(filename, config, argv=argv, verbose=False)
    nodes = {}
    for node in config.nodes:
        remaps = [f"{source}:={target}" for source, target in node.remap_args]
        nodes[node.namespace.rstrip("/") + "/" + node.name] = {
            "package": node.package,
            "type": node.type,
            "namespace": node.namespace,
            "argv": shlex.split(node.args or "") + remaps,
        }
    params = {key: config.params[key].value for key in sorted(config.params)}
    return {"nodes": nodes, "params": params}


if __name__ == "__main__":
    json.dump([dump(job) for job in json.load(sys.stdin)], sys.stdout)
