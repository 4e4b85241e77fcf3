"""``resolved.xmi``: the resolved architecture as pyecore's XMI, written in memory.

pyecore's writer is kept (its output is the format other EMF tools read back) and only
made cheaper: per save, each referenced element's path is computed once; per process,
each class's ID attribute and each feature's role in the file (skipped, attribute,
reference, containment) are looked up once. pyecore asks the metamodel all of these
again for every element and reference it writes, through pyecore's descriptors (most of
the time of writing a product's model). The metamodel does not change while spl runs
and the model does not change while its file is written, so neither do the answers.
tests/test_resolved_xmi.py checks the bytes equal to pyecore's own writer's.
"""

from __future__ import annotations

import io
from typing import Any

from lxml.etree import Element, QName, SubElement
from pyecore.resources import URI
from pyecore.resources.xmi import XMIResource

# A feature's role in the file, as pyecore's XMIResource._go_across decides it.
_SKIP, _ATTRIBUTE, _ATTRIBUTES, _REFERENCE, _REFERENCES, _CHILD, _CHILDREN, _OTHER = range(8)


class _InMemoryURI(URI):
    """Lets pyecore serialise into memory: the bundle is assembled before any write."""

    def __init__(self) -> None:
        super().__init__("resolved.xmi")
        self.buffer = io.BytesIO()

    def create_outstream(self) -> io.BytesIO:
        return self.buffer


def _role(feature: Any) -> tuple[Any, int, str, Any, Any]:
    """(feature, role, name, type, default) of a metamodel feature, looked up once per
    process (the feature is kept with it, so its id is never reused)."""
    known = _ROLES.get(id(feature))
    if known is None:
        etype, default = feature._eType, None
        if feature.derived or feature.transient:
            role = _SKIP
        elif etype is None or (hasattr(etype, "eType") and etype.eType is dict):
            role = _OTHER  # untyped (no default to compare with), map entries: pyecore's
        elif feature.is_attribute:
            role = _ATTRIBUTES if feature.many else _ATTRIBUTE
            default = feature.get_default_value()
        elif feature.eOpposite and feature.eOpposite.containment:
            role = _SKIP
        elif not feature.containment:
            role = _REFERENCES if feature.many else _REFERENCE
        else:
            role = _CHILDREN if feature.many else _CHILD
        known = _ROLES[id(feature)] = (feature, role, feature._name, etype, default)
    return known


_ROLES: dict[int, tuple[Any, int, str, Any, Any]] = {}
_ID_ATTRIBUTES: dict[int, tuple[Any, Any]] = {}


class _ResolvedXMI(XMIResource):
    """pyecore's XMI writer with the look-ups of the module docstring remembered."""

    def save(self, output: Any = None, options: Any = None) -> None:
        self._paths: dict[int, tuple[Any, tuple[str, bool]]] = {}
        try:
            super().save(output, options)
        finally:
            self._paths = {}

    def _build_path_from(self, obj: Any) -> tuple[str, bool]:
        """The reference to ``obj`` written in this file, computed once per element and
        save (pyecore walks up to the root for it at every reference)."""
        known = self._paths.get(id(obj))
        if known is None:
            known = self._paths[id(obj)] = (obj, super()._build_path_from(obj))
        return known[1]

    @staticmethod
    def get_id_attribute(eclass: Any) -> Any:
        known = _ID_ATTRIBUTES.get(id(eclass))
        if known is None:  # the class is kept with it, so its id is never reused
            known = _ID_ATTRIBUTES[id(eclass)] = (eclass, XMIResource.get_id_attribute(eclass))
        return known[1]

    def _go_across(self, obj: Any, serialize_default: bool = False) -> Any:
        """XMIResource._go_across with each feature's role from :func:`_role`; what
        this file never holds (default values written out, UUIDs, map entries) is
        left to pyecore's own."""
        roles = [_role(feature) for feature in obj._isset]
        if serialize_default or self.use_uuid or any(r[1] == _OTHER for r in roles):
            return super()._go_across(obj, serialize_default)
        eclass = obj.eClass
        containment = obj._containment_feature
        if containment:
            node = Element(containment._name)
            if containment._eType != eclass:
                self._add_explicit_type(node, obj)
        else:  # the root
            nsURI = eclass.ePackage.nsURI
            node = Element(QName(nsURI, eclass.name) if nsURI else eclass.name)
        attributes = node.attrib
        for _, role, name, etype, default in roles:
            if role == _SKIP:
                continue
            value = getattr(obj, name)
            if value is None:
                continue
            if role == _ATTRIBUTE:
                if value != default:
                    attributes[name] = etype.to_string(value)
            elif role == _ATTRIBUTES:
                if value:
                    self._attribute_values(node, name, etype, value)
                elif value != default:  # as pyecore: an empty list compared as one value
                    attributes[name] = etype.to_string(value)
            elif role == _REFERENCES:
                self._references(node, name, value)
            elif role == _REFERENCE:
                fragment, crossref = self._build_path_from(value)
                if crossref:
                    sub = SubElement(node, name)
                    sub.attrib["href"] = fragment
                    self._add_explicit_type(sub, value)
                else:
                    attributes[name] = fragment
            elif role == _CHILD:
                node.append(self._go_across(value))
            else:
                for child in value:
                    node.append(self._go_across(child))
        return node

    def _attribute_values(self, node: Any, name: str, etype: Any, values: Any) -> None:
        to_string = etype.to_string
        texts = [None if v is None else to_string(v) for v in values]
        if any(not text or any(x.isspace() for x in text) for text in texts):
            for text in texts:
                if text is None:
                    node.append(self._build_none_node(name))
                else:
                    SubElement(node, name).text = text
        else:
            node.attrib[name] = " ".join(texts)  # type: ignore[arg-type]

    def _references(self, node: Any, name: str, values: Any) -> None:
        embedded = []
        crossrefs = []
        for i, value in enumerate(values):
            fragment, crossref = self._build_path_from(value)
            if crossref:
                crossrefs.append((i, fragment))
            else:
                embedded.append(fragment)
        if embedded:
            node.attrib[name] = " ".join(embedded)
        for i, fragment in crossrefs:
            sub = SubElement(node, name)
            sub.attrib["href"] = fragment
            self._add_explicit_type(sub, values[i])


def resolved_xmi(system: Any) -> bytes:
    """The model under ``system`` as XMI bytes (the model is put in a resource for the
    write and taken out again)."""
    resource = _ResolvedXMI(URI("resolved.xmi"))
    resource.append(system)
    output = _InMemoryURI()
    try:
        resource.save(output=output)
    finally:
        resource.remove(system)
    return output.buffer.getvalue()
