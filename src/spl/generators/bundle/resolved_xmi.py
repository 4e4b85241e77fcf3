"""``resolved.xmi``: the resolved architecture as pyecore's XMI, written in memory.

The file is what pyecore's XMI writer writes (the format other EMF tools read back),
byte for byte. For the models spl writes (one package, references inside the file, text
an XML file can hold) the text is written directly, as lxml's pretty printer lays out the
elements pyecore builds, each feature's role in the file (skipped, attribute, reference,
containment) looked up once per file or per run (:class:`MetamodelRoles`): pyecore
builds an lxml element per model element and asks the metamodel these questions again
for every element and reference it writes, through its descriptors (a product's model
took about 1.2 ms; the text takes a half of that). Every other model goes through
pyecore's writer itself. tests/generators/test_resolved_xmi.py checks the bytes equal to
pyecore's own writer's.
"""

from __future__ import annotations

import io
import re
from typing import TYPE_CHECKING, cast

from pyecore.resources import URI
from pyecore.resources.xmi import XMI_URL, XSI_URL, XMIResource

if TYPE_CHECKING:  # pyecore's reflective classes: the writer reads any model through them
    from pyecore.ecore import EClass, EDataType, EObject, EStructuralFeature

    # (feature, role, name, type, default): what the writer asks of a feature
    Role = tuple[EStructuralFeature, int, str, EDataType | EClass | None, object]

# A feature's role in the file, as pyecore's XMIResource._go_across decides it.
_SKIP, _ATTRIBUTE, _ATTRIBUTES, _REFERENCE, _REFERENCES, _CHILD, _CHILDREN, _OTHER = range(8)


class _InMemoryURI(URI):
    """Lets pyecore serialise into memory: the bundle is assembled before any write."""

    def __init__(self) -> None:
        super().__init__("resolved.xmi")
        self.buffer = io.BytesIO()

    def create_outstream(self) -> io.BytesIO:
        return self.buffer


def _role(feature: EStructuralFeature) -> Role:
    """(feature, role, name, type, default) of a metamodel feature."""
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
    return (feature, role, feature._name, etype, default)


# Text lxml writes in an attribute escaping only these: characters XML allows (lxml
# refuses the others, and that refusal is left to it).
_ALLOWED = re.compile("[\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]*")
_ESCAPES = str.maketrans(
    {
        "&": "&amp;",
        "<": "&lt;",
        ">": "&gt;",
        '"': "&quot;",
        "\t": "&#9;",
        "\n": "&#10;",
        "\r": "&#13;",
    }
)


class MetamodelRoles:
    """Each feature's role in the file and each class's ID attribute, looked up once by
    whoever keeps this (a bundle, or a run writing many: :class:`BundleMemo
    <spl.generators.bundle.inputs.BundleMemo>`); by id, as the metamodel holding them
    outlives every file."""

    def __init__(self) -> None:
        self.roles: dict[int, Role] = {}
        self.id_attributes: dict[int, EStructuralFeature | None] = {}


class _Elsewhere(Exception):
    """Something the direct text does not cover: pyecore's writer writes the model."""


def _quoted(text: str) -> str:
    if not _ALLOWED.fullmatch(text):
        raise _Elsewhere
    return text.translate(_ESCAPES)


class _XMIText:
    """The text pyecore's writer and lxml's pretty printer make of a model in one package
    whose references all point inside it; :class:`_Elsewhere` for anything else. A
    reference may point to an element written later, so the text is gathered as pieces in
    which a referenced element stands for its path (its URI fragment,
    ``//@containers.0/@topics.5``), filled in once every path is known."""

    def __init__(self, root: EObject, known: MetamodelRoles | None = None) -> None:
        known = MetamodelRoles() if known is None else known
        self.package = root.eClass.ePackage
        self.prefix = self.package.nsPrefix
        if not self.package.nsURI or not self.prefix or self.prefix in ("xmi", "xsi"):
            raise _Elsewhere
        self.paths = {id(root): "/"}
        self.typed = False  # an xsi:type written: the root declares the xsi namespace
        self.roles = known.roles
        self.id_attributes = known.id_attributes
        # text, or a referenced element standing for its path (None: the root's start tag)
        self.out: list[str | EObject | None] = []

    def document(self, root: EObject) -> bytes:
        tag = f"{self.prefix}:{root.eClass.name}"
        out = self.out
        out.append(None)  # the root's start tag, known once its children are written
        children = self._content(root, "/")
        end = len(out)
        self._children(children, 1)
        namespaces = [("xmi", XMI_URL), (self.prefix, self.package.nsURI)]
        if self.typed:
            namespaces.append(("xsi", XSI_URL))
        declared = "".join(f' xmlns:{prefix}="{_quoted(uri)}"' for prefix, uri in namespaces)
        out[0] = f"<?xml version='1.0' encoding='UTF-8'?>\n<{tag}{declared}"
        if children:
            out.insert(end, ' xmi:version="2.0">\n')
            out.append(f"</{tag}>\n")
        else:
            out.append(' xmi:version="2.0"/>\n')
        paths = self.paths
        try:
            text = "".join(piece if type(piece) is str else paths[id(piece)] for piece in out)
        except KeyError:
            raise _Elsewhere from None  # a reference out of the file
        return text.encode()

    def _content(self, obj: EObject, path: str) -> list[tuple[EObject, str]]:
        """Writes the element's attributes, in the order pyecore writes them (the order
        the features were set); returns its children with their tags, their paths known."""
        out, paths, roles = self.out, self.paths, self.roles
        children: list[tuple[EObject, str]] = []
        for feature in obj._isset:
            known = roles.get(id(feature))
            if known is None:
                known = roles[id(feature)] = _role(feature)
            _, role, name, etype, default = known
            if role == _SKIP:
                continue
            if role in (_OTHER, _ATTRIBUTES):
                raise _Elsewhere
            value = getattr(obj, name)
            if value is None:
                continue
            if role == _ATTRIBUTE:
                if value != default:
                    text = cast("EDataType", etype).to_string(value)  # an attribute's type
                    out.append(f' {name}="{_quoted(text)}"')
            elif role == _REFERENCE:
                out.extend((f' {name}="', self._referable(value), '"'))
            elif role == _REFERENCES:
                if value:
                    out.append(f' {name}="')
                    for index, target in enumerate(value):
                        referable = self._referable(target)
                        out.extend((" ", referable) if index else (referable,))
                    out.append('"')
            elif role == _CHILD:
                paths[id(value)] = f"{path}/@{name}"
                children.append((value, name))
            else:
                for index, child in enumerate(value):
                    paths[id(child)] = f"{path}/@{name}.{index}"
                    children.append((child, name))
        return children

    def _children(self, children: list[tuple[EObject, str]], depth: int) -> None:
        out, indent = self.out, "  " * depth
        for obj, tag in children:
            eclass = obj.eClass
            if obj._containment_feature._eType is eclass:
                out.append(f"{indent}<{tag}")
            elif eclass.ePackage is self.package:
                out.append(f'{indent}<{tag} xsi:type="{self.prefix}:{eclass.name}"')
                self.typed = True
            else:
                raise _Elsewhere
            inner = self._content(obj, self.paths[id(obj)])
            if inner:
                out.append(">\n")
                self._children(inner, depth + 1)
                out.append(f"{indent}</{tag}>\n")
            else:
                out.append("/>\n")

    def _referable(self, target: EObject) -> EObject:
        """The referenced element, standing for its path; one with an ID attribute is
        referred to by its ID, which is left to pyecore (so is a reference pyecore holds
        as text, an href it never resolved)."""
        if type(target) is str:
            raise _Elsewhere
        eclass = target.eClass
        known = self.id_attributes.get(id(eclass), False)
        if known is False:
            known = self.id_attributes[id(eclass)] = XMIResource.get_id_attribute(eclass)
        if known:
            raise _Elsewhere
        return target


def resolved_xmi(system: EObject, known: MetamodelRoles | None = None) -> bytes:
    """The model under ``system`` as XMI bytes (for another model than spl's, the model
    is put in a resource for pyecore's write and taken out again); ``known``: the roles
    looked up so far by the caller's files, else this file's own."""
    if system.eContainer() is None and system.eResource is None:
        try:
            return _XMIText(system, known).document(system)
        except _Elsewhere:
            pass
    resource = XMIResource(URI("resolved.xmi"))
    resource.append(system)
    output = _InMemoryURI()
    try:
        resource.save(output=output)
    finally:
        resource.remove(system)
    return output.buffer.getvalue()
