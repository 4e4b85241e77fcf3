"""A product line on disk: one folder with a .rm (naming its .tsm and .fm) and
``products/*.yaml``. Parsed once and reused for every product derived from it."""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

from spl.core.cyclic_gc import without_cyclic_gc
from spl.core.diagnostics import Diagnostic, Location, ModelError
from spl.dsl.rm import language as rm

if TYPE_CHECKING:
    from spl.core.emf_copy import TreeImage
    from spl.dsl.workspace import Workspace
    from spl.metamodels import fm_types, rm_types, tsm_types
    from spl.resolver.analysis.formula import FeatureModelFormula
    from spl.resolver.architecture.flows import FlowTable

Fact = TypeVar("Fact")


class TemplateFacts:
    """The facts of a line's template that read nothing but the template, kept in the
    editor's memory of the line (:class:`spl.dsl.workspace.LineMemory`) while the line's
    template is the same model: an edit of the .rm or .fm builds no .tsm again
    (:class:`spl.dsl.workspace.LastModels`), and its check then finds them as they were
    (docs/editors.md, "What the editor keeps"). A template is never changed once built,
    and a new build is a new model, so the model's identity tells when they are right."""

    def __init__(self) -> None:
        self._system: Any = None
        self._facts: dict[str, Any] = {}
        self.made: Counter[str] = Counter()  # how often each fact was computed

    def follow(self, system: tsm_types.System) -> None:
        """The line's template is now ``system``: the facts of another are let go."""
        if system is not self._system:
            self._system, self._facts = system, {}

    def of(self, system: tsm_types.System, name: str, compute: Callable[[], Fact]) -> Fact:
        """The fact ``name`` of ``system``, computed by ``compute`` unless kept."""
        self.follow(system)
        if name not in self._facts:
            self._facts[name] = compute()
            self.made[name] += 1
        return self._facts[name]


@dataclass(eq=False)
class ProductLine:
    directory: Path
    models: rm.ResolutionModelFiles
    # the template's facts the editor keeps for this line; None: computed for this line
    kept: TemplateFacts | None = None

    @property
    def tsm(self) -> tsm_types.System:
        return self.models.tsm

    @property
    def fm(self) -> fm_types.FeatureModel:
        return self.models.fm

    @property
    def rm(self) -> rm_types.ResolutionModel:
        return self.models.rm

    @cached_property
    def formula(self) -> FeatureModelFormula:
        """The feature model's CNF in an incremental solver, built once for every product."""
        from spl.resolver.analysis.formula import formula_of

        return formula_of(self.fm)

    @cached_property
    def template_image(self) -> TreeImage:
        """The template read once for the copy each product's resolution starts from
        (:class:`spl.core.emf_copy.TreeImage`): a line check resolves dozens of witness
        products of one line."""
        from spl.core.emf_copy import TreeImage

        return self._template_fact("template_image", lambda: TreeImage([self.tsm]))

    @cached_property
    def template_flows(self) -> FlowTable:
        """Who talks to whom in the template (before any resolution), built once for the
        line checks that follow data through it."""
        from spl.resolver.architecture.flows import FlowTable

        return self._template_fact("template_flows", lambda: FlowTable.of(self.tsm))

    @cached_property
    def node_keepers(self) -> dict[int, list[rm_types.ResolutionElement]]:
        """The resolution elements that keep each node they require or transform, by
        the node's id, in file order
        (:func:`spl.resolver.resolution.transformations.touched_elements`,
        what the engine keeps), built once for the line checks."""
        from spl.resolver.resolution.transformations import touched_elements

        keeping: dict[int, list[rm_types.ResolutionElement]] = {}
        for element in self.rm.elements:
            for node in touched_elements(element):
                kept_by = keeping.setdefault(id(node), [])
                if not kept_by or kept_by[-1] is not element:  # required and transformed
                    kept_by.append(element)
        return keeping

    @cached_property
    def template_reach(self) -> dict[int, list[tsm_types.Topic]]:
        """The topics data put on each topic of the template reaches, by its bridges
        (:func:`spl.resolver.architecture.flows.reached_topics`), built once for the line checks."""
        from spl.resolver.architecture.flows import reached_topics

        return self._template_fact("template_reach", lambda: reached_topics(self.tsm))

    @cached_property
    def unreferred_optionals(self) -> dict[int, int]:
        """The template's optional nodes and stores nothing else in it refers into, and
        what they hold (:func:`spl.resolver.resolution.pruning.unreferred_optionals`), found once:
        a product whose elements name none of one leaves it out of its copy."""
        from spl.resolver.resolution.pruning import unreferred_optionals

        return self._template_fact("unreferred_optionals", lambda: unreferred_optionals(self.tsm))

    def _template_fact(self, name: str, compute: Callable[[], Fact]) -> Fact:
        """A fact of the template alone: kept by the editor for its template, if it keeps any."""
        return compute() if self.kept is None else self.kept.of(self.tsm, name, compute)

    @property
    def name(self) -> str:
        return self.directory.resolve().name

    def product_files(self) -> list[Path]:
        """The products the line's authors listed (``products/*.yaml``), by name."""
        return sorted((self.directory / "products").glob("*.yaml"))


def find_resolution_model(directory: Path) -> Path:
    """The line's one .rm; a ModelError when there is none, or one error at each .rm
    after the first (by name), so an editor shows it on the file to remove or move."""
    found = sorted(directory.glob("*.rm"))
    if not found:
        raise ModelError(
            [Diagnostic(Location(str(directory), 0, 0), "a product line holds one .rm; found none")]
        )
    if len(found) > 1:
        raise ModelError(
            [
                Diagnostic(
                    Location(str(extra), 1, 1),
                    f"a product line holds one .rm, and {found[0].name} is this folder's first: "
                    f"move or remove {extra.name}",
                )
                for extra in found[1:]
            ]
        )
    return found[0]


def load_product_line(directory: str | Path, workspace: Workspace | None = None) -> ProductLine:
    """The line in ``directory``; its models read as the editor's ``workspace`` has them,
    when given (:mod:`spl.dsl.workspace`), and the template's facts kept in its memory of
    the line, if it keeps one (:class:`TemplateFacts`)."""
    directory = Path(directory)
    with without_cyclic_gc():  # the models live on: the collector need not walk them
        line = ProductLine(directory, rm.load(find_resolution_model(directory), workspace))
    memory = workspace.line_memory(directory) if workspace is not None else None
    if memory is not None:
        line.kept = memory.of(TemplateFacts)
        line.kept.follow(line.tsm)
    return line
