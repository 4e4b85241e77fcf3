"""A model copy (the Resolution Engine's step 3) is the original again, element for
element, and a model pyecore handles as any other: attributes set as pyecore sets them,
containers and references in place, edits and listeners on the copy working."""

from __future__ import annotations

from pathlib import Path

import pytest
from pyecore.notification import EObserver

from spl.core.emf import copy_with_map
from spl.core.emf_compare import differences
from spl.dsl.tsm.language import parse_file

MODELS = sorted((Path(__file__).resolve().parents[2] / "product_lines").glob("*/*.tsm"))


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.stem)
def test_a_copy_equals_its_original_and_maps_every_element(path):
    original = parse_file(path)
    copy, mapping = copy_with_map(original)
    assert list(differences(original, copy)) == []
    elements = [original, *original.eAllContents()]
    assert all(mapping[id(e)] is not e for e in elements)
    for element in elements:
        twin = mapping[id(element)]
        assert twin.eClass is element.eClass
        container = element.eContainer()
        assert twin.eContainer() is (mapping[id(container)] if container else None)
        for feature in element.eClass.eAllAttributes():
            if not feature.many:  # a default value is left unset in the copy
                value = getattr(element, feature.name)
                assert getattr(twin, feature.name) == value
                explicit = value is not None and value != feature.get_default_value()
                assert twin.eIsSet(feature) == explicit, feature.name


def test_edits_and_listeners_on_a_copy_work_and_leave_the_original_alone():
    original = parse_file(MODELS[0])
    copy, _ = copy_with_map(original)
    node = next(n for c in copy.containers for n in c.nodes)
    heard = []

    class Listener(EObserver):
        def notifyChanged(self, notification):
            heard.append((notification.feature.name, notification.new))

    Listener(notifier=node)
    before = {id(n): n.name for c in original.containers for n in c.nodes}
    node.name = "Renamed"
    assert heard == [("name", "Renamed")]
    assert node.name == "Renamed"
    assert {id(n): n.name for c in original.containers for n in c.nodes} == before


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.stem)
def test_a_copied_attribute_slot_is_the_one_pyecore_builds(path):
    from pyecore.valuecontainer import EValue

    original = parse_file(path)
    _, mapping = copy_with_map(original)
    compared = 0
    for element in [original, *original.eAllContents()]:
        twin = mapping[id(element)]
        for feature in element.eClass.eAllAttributes():
            slot = twin.__dict__.get(feature.name)
            if feature.many or slot is None:
                continue
            own = EValue(twin, feature)
            own._value = getattr(element, feature.name)
            assert type(slot) is EValue and vars(slot) == vars(own), feature.name
            compared += 1
    assert compared > 0


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.stem)
def test_a_copy_is_the_one_pyecore_builds_by_setting_each_feature(path, monkeypatch):
    """Slots, set features, containers and inverse relations of every copied element
    equal those of a copy whose features are all set through pyecore's descriptors."""
    from spl.core import emf_copy as emf

    original = parse_file(path)
    _, fast_map = copy_with_map(original)
    monkeypatch.setattr(
        emf, "_set_attribute", lambda obj, _, name, value: setattr(obj, name, value)
    )
    monkeypatch.setattr(
        emf, "_set_reference", lambda obj, _, name, value, __: setattr(obj, name, value)
    )
    monkeypatch.setattr(
        emf, "extend", lambda obj, _, name, values, __: getattr(obj, name).extend(values)
    )
    monkeypatch.setattr(
        emf, "_set_attributes", lambda obj, found: [setattr(obj, n, v) for n, _, v in found]
    )
    monkeypatch.setattr(emf, "new_element", lambda python_class: python_class())
    _, slow_map = copy_with_map(original)
    to_slow = {id(fast_map[key]): slow_map[key] for key in fast_map}

    def same(value):
        return to_slow.get(id(value), value)

    compared = 0
    for element in [original, *original.eAllContents()]:
        a, b = fast_map[id(element)], slow_map[id(element)]
        assert list(a._isset) == list(b._isset)  # in order: resolved.xmi writes them so
        assert same(a.eContainer()) is b.eContainer()
        assert a._containment_feature is b._containment_feature
        assert {(same(owner), f) for owner, f in a._inverse_rels} == {
            (owner, f) for owner, f in b._inverse_rels
        }
        for feature in element.eClass.eAllStructuralFeatures():
            slot, own = a.__dict__.get(feature.name), b.__dict__.get(feature.name)
            if feature.many:
                if getattr(element, feature.name):
                    assert type(slot) is type(own), feature.name
                    assert [same(v) for v in slot] == list(own), feature.name
                    fields = {
                        k: same(v) for k, v in vars(slot).items() if k not in ("items", "map")
                    }
                    assert fields == {
                        k: v for k, v in vars(own).items() if k not in ("items", "map")
                    }
                    compared += 1
                continue
            assert (slot is None) == (own is None), feature.name
            if slot is not None:
                fields = {k: same(v) for k, v in vars(slot).items()}
                assert type(slot) is type(own) and fields == vars(own), feature.name
                compared += 1
    assert compared > 0


@pytest.mark.parametrize("count", [3, 12])  # the few one by one, many in one pass
def test_removing_many_members_leaves_what_removing_each_leaves(count):
    """A product dropping many optional nodes of one container (spl.core.emf.remove_all):
    the same members in the same order, the removed ones detached, the kept ones
    contained, as when pyecore removes each."""
    from spl.core.emf import remove_all
    from spl.metamodels import tsm

    T = tsm()
    one_by_one, at_once = T.CloudContainer(name="a"), T.CloudContainer(name="b")
    for container in (one_by_one, at_once):
        container.nodes.extend(T.Node(name=f"N{i}") for i in range(2 * count))
    for container, remove in ((one_by_one, None), (at_once, remove_all)):
        dropped = [n for i, n in enumerate(container.nodes) if i % 2]
        if remove is None:
            for node in dropped:
                container.nodes.remove(node)
        else:
            remove(container.nodes, dropped)
        assert [n.name for n in container.nodes] == [f"N{i}" for i in range(0, 2 * count, 2)]
        assert all(n.eContainer() is container for n in container.nodes)
        assert all(n.eContainer() is None for n in dropped)
        container.nodes.append(dropped[0])  # a member removed can be added again
        assert container.nodes[-1] is dropped[0] and dropped[0].eContainer() is container


def test_an_element_made_for_a_copy_is_the_one_pyecore_makes():
    """Every class of the .tsm metamodel: the same state, known to pyecore's instances."""
    from pyecore.ecore import EObject

    from spl.core.emf_copy import new_element
    from spl.metamodels import tsm

    classes = [c for c in tsm().package.eClassifiers if getattr(c, "abstract", True) is False]
    assert classes
    for eclass in classes:
        fast, own = new_element(eclass.python_class), eclass.python_class()
        assert type(fast) is type(own)
        assert vars(fast).keys() == vars(own).keys(), eclass.name
        for key, value in vars(own).items():
            mine = vars(fast)[key]
            if key == "dyn_inst":
                assert mine is fast
            else:
                assert type(mine) is type(value) and mine == value, (eclass.name, key)
        assert fast in set(EObject.allInstances())


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.stem)
def test_one_image_gives_as_many_separate_copies_as_asked(path):
    """A line's template read once serves every product's resolution: each copy equals
    the original, and an edit of one reaches neither the others nor the original."""
    from spl.core.emf_copy import TreeImage

    original = parse_file(path)
    image = TreeImage([original])
    [first], _ = image.copy()
    [second], _ = image.copy()
    assert list(differences(original, first)) == []
    node = next(n for c in first.containers for n in c.nodes)
    node.name = "Renamed"
    assert list(differences(original, second)) == []
    assert "Renamed" not in {n.name for c in original.containers for n in c.nodes}
