"""Launch files read by roslaunch's own loader, run by the Python that has roslaunch.

This file is executed as a script by the interpreter of Debian's ROS 1 (``python3 -I
roslaunch_reader.py``), never imported by spl itself: roslaunch is importable only there,
and ``-I`` keeps the virtual environment's packages off its ``sys.path``. It imports
nothing from spl. The request (JSON on stdin) names the launch files, the argument
combinations and the folders files may come from; the answer (JSON on stdout) is, per
combination, the nodes and parameters roslaunch's ``XmlLoader`` put into its
``ROSLaunchConfig``, and what was left out, located (docs/import.md).

The loader is roslaunch's, with five changes, all about hostile or unknowable input:

- no command is ever run: ``<param command=...>`` (xacro) is left out, located;
- a file is read only inside the allowed folders, at most ``max_bytes`` long, without a
  DTD (so no entity expansion), and includes nest at most ``MAX_DEPTH`` deep;
- a value roslaunch cannot know here (a package missing from the package path, an unset
  ``$(env)``, a failing ``$(eval)``, a random ``$(anon)``) leaves out the tag that needs
  it, located, instead of failing the whole file;
- ``<test>`` is left out, located: a test is not part of the application;
- the elements are parsed with their line numbers, which minidom does not keep.
"""

from __future__ import annotations

import json
import os
import sys
from xml.dom import Node as DomNode, expatbuilder
from xml.parsers.expat import ErrorString, ExpatError

import yaml
from roslaunch import xmlloader
from roslaunch.config import ROSLaunchConfig
from roslaunch.core import RLException
from rospkg import ResourceNotFound

MAX_DEPTH = 40  # includes inside includes; a cycle stops here
MAX_FILES = 2000  # launch files read for one combination
MAX_VALUE_ITEMS = 200_000  # scalars in one rosparam file's value, aliases counted


class Refused(BaseException):
    """The input is refused as a whole (nothing is written). A BaseException, so that
    roslaunch's ``except Exception`` handlers pass it on unchanged."""


class LeftOut(BaseException):
    """The tag being loaded needs something unknowable here; it is left out, located."""


class _LineBuilder(expatbuilder.ExpatBuilder):
    """minidom's builder, keeping each element's line and refusing any DTD."""

    def install(self, parser):
        super().install(parser)
        self.lines = parser
        parser.StartDoctypeDeclHandler = self._refuse_doctype
        parser.EntityDeclHandler = self._refuse_doctype

    def _refuse_doctype(self, *_args):
        raise Refused("a DOCTYPE or entity declaration (refused: entity expansion)")

    def start_element_handler(self, name, attributes):
        super().start_element_handler(name, attributes)
        setattr(self.curNode, "spl_line", self.lines.CurrentLineNumber)  # noqa: B010

    first_element_handler = start_element_handler


def _line(tag):
    return getattr(tag, "spl_line", 0)


def _count_items(value, budget):
    """``budget`` less the scalars of ``value``; below zero once it is too large."""
    stack = [value]
    while stack and budget >= 0:
        item = stack.pop()
        budget -= 1
        if isinstance(item, dict):
            stack.extend(item.values())
        elif isinstance(item, list):
            stack.extend(item)
    return budget


class ImportLoader(xmlloader.XmlLoader):
    def __init__(self, roots, max_bytes):
        super().__init__(resolve_anon=True)
        self.roots = [os.path.realpath(r) for r in roots]
        self.max_bytes = max_bytes
        self.warnings = []
        self.where = []  # (file, line) of the tags being loaded, innermost last
        self.left_out_args = set()
        self.files = 0
        self.depth = 0
        self.node_lines = {}
        self.machine_places = {}
        self.declared = set()
        self.ignore_unset_args = False  # roslaunch's command line sets it so

    # -- files ------------------------------------------------------------------------
    def _checked_path(self, filename, what):
        real = os.path.realpath(filename)
        if not any(real == r or real.startswith(r + os.sep) for r in self.roots):
            raise Refused(f"{what} {filename} is outside the package path")
        try:
            size = os.path.getsize(real)
        except OSError as exc:
            raise Refused(f"{what} {filename} cannot be read: {exc.strerror}") from None
        if size > self.max_bytes:
            raise Refused(f"{what} {filename} is {size} bytes, more than {self.max_bytes}")
        return real

    def _parse_launch(self, filename, verbose):
        self.files += 1
        if self.files > MAX_FILES:
            raise Refused(f"more than {MAX_FILES} launch files read for one combination")
        real = self._checked_path(filename, "launch file")
        try:
            with open(real, "rb") as stream:
                document = _LineBuilder().parseFile(stream)
        except Refused as exc:
            raise Refused(f"{filename}: {exc}") from None
        except ExpatError as exc:  # at its line and column (expat's count from 0)
            reason = ErrorString(exc.code)
            raise Refused(
                f"{filename}:{exc.lineno}:{exc.offset + 1}: invalid launch XML: {reason}"
            ) from None
        except Exception as exc:
            raise Refused(f"{filename}: invalid launch XML: {exc}") from None
        roots = document.getElementsByTagName("launch")
        if len(roots) != 1:
            raise Refused(f"{filename}: invalid launch XML: no single root <launch> tag")
        return roots[0]

    def load_rosparam(
        self, context, ros_config, cmd, param, file_, text, verbose=True, subst_function=None
    ):
        if cmd in ("dump", "delete"):
            raise LeftOut(f'<rosparam command="{cmd}"> runs rosparam at launch time')
        if file_ is not None and (cmd or "load") == "load":
            with open(self._checked_path(file_, "parameter file"), encoding="utf-8") as f:
                text, file_ = f.read(), None
        if subst_function is not None:
            text, subst_function = subst_function(text), None
        try:
            value = yaml.safe_load(text)
        except yaml.YAMLError:
            value = None  # roslaunch reports it below, with its own words
        if _count_items(value, MAX_VALUE_ITEMS) < 0:
            raise Refused(f"a rosparam value of more than {MAX_VALUE_ITEMS} items (YAML aliases?)")
        super().load_rosparam(context, ros_config, cmd, param, file_, text, verbose, subst_function)

    def param_value(self, verbose, name, ptype, value, textfile, binfile, command):
        if command is not None:
            raise LeftOut("<param command=...> would run a command")
        for path in (textfile, binfile):
            if path is not None:
                self._checked_path(path, "parameter file")
        return super().param_value(verbose, name, ptype, value, textfile, binfile, None)

    # -- values roslaunch cannot know here --------------------------------------------
    def resolve_args(self, args, context):
        if args and "$(anon" in args:
            raise LeftOut(f"{args!r}: $(anon) gives a random name on every run")
        try:
            return super().resolve_args(args, context)
        except ResourceNotFound as exc:
            raise LeftOut(f"package {_first_line(exc)} is not in the package path") from None
        except xmlloader.ArgException as exc:
            if str(exc) in self.left_out_args:
                raise LeftOut(f"it uses arg {exc}, which was left out") from None
            raise
        except xmlloader.SubstitutionException as exc:
            if "environment variable" in str(exc) or args.lstrip().startswith("$(eval"):
                raise LeftOut(f"{args!r}: {exc}") from None
            raise
        except Exception as exc:  # a $(eval ...) whose Python fails
            if args.lstrip().startswith("$(eval"):
                raise LeftOut(f"{args!r}: the value of $(eval) is unknown ({exc})") from None
            raise

    def _arg_tag(self, tag, context, ros_config, verbose=True):
        if self.depth == 0:  # an argument of a file given, which --arg may set
            self.declared.add(tag.getAttribute("name"))
        try:
            return super()._arg_tag(tag, context, ros_config, verbose=verbose)
        except LeftOut:
            name = tag.getAttribute("name")
            given = (context.include_resolve_dict or context.resolve_dict).get("arg", {})
            if tag.hasAttribute("default") and name in given:
                # the default roslaunch evaluates anyway is not needed: the value is given
                context.add_arg(name, default="", doc=None)
                return None
            self.left_out_args.add(name)
            raise

    def _param_tag(self, tag, context, ros_config, force_local=False, verbose=True):
        if tag.hasAttribute("command") and xmlloader.ifunless_test(self, tag, context):
            self._warn(
                context.filename,
                _line(tag),
                f'<param name="{tag.getAttribute("name")}" command=...> left out: '
                "spl runs no command while importing (its output is not known)",
            )
            return None
        return super()._param_tag(tag, context, ros_config, force_local, verbose)

    def _node_tag(self, tag, context, ros_config, default_machine, is_test=False, verbose=True):
        node = super()._node_tag(tag, context, ros_config, default_machine, is_test, verbose)
        if node is not None:
            self.node_lines[id(node)] = _line(tag)  # a roslaunch Node has __slots__
        return node

    def _machine_tag(self, tag, context, ros_config, verbose=True):
        found = super()._machine_tag(tag, context, ros_config, verbose=verbose)
        if found is not None:
            self.machine_places[found[0].name] = (context.filename, _line(tag))
        return found

    def _include_tag(self, tag, context, ros_config, default_machine, is_core, verbose):
        self.depth += 1
        try:
            if self.depth > MAX_DEPTH:
                filename, line = self.where[-1] if self.where else (context.filename, 0)
                raise Refused(
                    f"{filename}:{line}: includes nested more than {MAX_DEPTH} deep (a cycle?)"
                )
            return super()._include_tag(tag, context, ros_config, default_machine, is_core, verbose)
        finally:
            self.depth -= 1

    def _recurse_load(self, ros_config, tags, context, default_machine, is_core, verbose):
        """roslaunch's loop, one tag at a time, so that a tag left out is only that one."""
        for tag in [t for t in tags if t.nodeType == DomNode.ELEMENT_NODE]:
            where = (context.filename, _line(tag))
            self.where.append(where)
            try:
                if tag.tagName == "test":
                    if xmlloader.ifunless_test(self, tag, context):
                        self._warn(
                            *where,
                            f'<test test-name="{tag.getAttribute("test-name")}">'
                            " left out: a test is not part of the application",
                        )
                    continue
                default_machine = super()._recurse_load(
                    ros_config, [tag], context, default_machine, is_core, verbose
                )
            except LeftOut as exc:
                if self.where[-1] != where:
                    raise  # an inner tag's: reported there
                self._warn(*where, f"<{tag.tagName}{_named(tag)}> left out: {exc}")
            except Refused:
                raise
            except xmlloader.ArgException as exc:
                raise Refused(
                    f"{where[0]}:{where[1]}: <{tag.tagName}{_named(tag)}> needs arg '{exc}', "
                    "which is not set (an argument of the file given: --arg NAME=VALUE)"
                ) from None
            except (RLException, ValueError) as exc:  # ValueError: a value of the wrong type
                raise Refused(f"{where[0]}:{where[1]}: {_first_line(exc)}") from None
            finally:
                if self.where and self.where[-1] == where:
                    self.where.pop()
        return default_machine

    def _warn(self, filename, line, message):
        self.warnings.append({"file": filename, "line": line, "message": message})


def _named(tag):
    for attribute in ("name", "file", "param", "pkg"):
        if tag.hasAttribute(attribute):
            return f' {attribute}="{tag.getAttribute(attribute)}"'
    return ""


def _first_line(exc):
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__


def _plain(value):
    """``value`` as JSON can carry it exactly, or None (a type ROS cannot send as is)."""
    if isinstance(value, (bool, int, float, str)):
        return value
    if isinstance(value, list):
        listed = [_plain(v) for v in value]
        return None if any(i is None for i in listed) else listed
    if isinstance(value, dict) and all(isinstance(k, str) for k in value):
        mapped = {k: _plain(v) for k, v in value.items()}
        return None if any(i is None for i in mapped.values()) else mapped
    return None


def load(files, arguments, roots, max_bytes):
    config = ROSLaunchConfig()
    reader = ImportLoader(roots, max_bytes)
    where_set: dict[str, tuple[str, int]] = {}
    add_param = config.add_param

    def located_add_param(p, filename=None, verbose=True):
        where_set.setdefault(p.key, reader.where[-1] if reader.where else ("", 0))
        return add_param(p, filename=filename, verbose=verbose)

    config.add_param = located_add_param  # where each parameter was set, for warnings
    argv = ["roslaunch"] + [f"{name}:={value}" for name, value in arguments]
    for filename in files:
        try:
            reader.load(filename, config, argv=argv, verbose=False)
        except Refused:
            raise
        except RLException as exc:
            raise Refused(f"{filename}: {_first_line(exc)}") from None
    unknown = [name for name, _ in arguments if name not in reader.declared]
    if unknown:  # roslaunch ignores it: every product would be the same
        raise Refused(
            f'--arg {unknown[0]}: no launch file given declares <arg name="{unknown[0]}">'
        )
    warnings = reader.warnings
    nodes = []
    for node in config.nodes:
        nodes.append(
            {
                "name": node.name,
                "namespace": node.namespace,
                "package": node.package,
                "type": node.type,
                "args": node.args or "",
                "machine": node.machine_name or "",
                "remaps": [list(r) for r in node.remap_args],
                "file": node.filename,
                "line": reader.node_lines.get(id(node), 0),
                "env": [list(e) for e in node.env_args],
                "respawn": bool(node.respawn),
                "launch_prefix": node.launch_prefix or "",
                "cwd": node.cwd or "",
            }
        )
    params = {}
    for key in sorted(config.params):
        value = _plain(config.params[key].value)
        kind = type(config.params[key].value).__name__
        if value is None:
            filename, line = where_set.get(key, ("", 0))
            warnings.append(
                {
                    "file": filename,
                    "line": line,
                    "message": f"parameter {key} left out: a {kind} value",
                }
            )
        else:
            params[key] = value
    machines = [
        {"name": name, "address": config.machines[name].address, "place": list(place)}
        for name, place in reader.machine_places.items()
        if name in config.machines
    ]
    return {
        "nodes": nodes,
        "params": params,
        "warnings": warnings,
        "machines": machines,
        "param_lines": {k: list(where_set.get(k, ("", 0))) for k in params},
    }


def main():
    request = json.load(sys.stdin)
    sys.setrecursionlimit(10_000)
    answer = []
    try:
        for combination in request["combinations"]:
            answer.append(
                load(request["files"], combination, request["roots"], request["max_bytes"])
            )
    except Refused as exc:
        json.dump({"refused": str(exc)}, sys.stdout)
        return
    json.dump({"combinations": answer}, sys.stdout)


if __name__ == "__main__":
    main()
