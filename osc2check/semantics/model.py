"""The Model: every declaration of a program and what each name refers to.

A program's model sits on top of the standard library's model (``base``),
which is built once per process and never changed: declarations that a
program adds to library types (``extend``, new actions of ``vehicle``) are
kept in the program's own tables. Resolution results are side tables keyed
by AST node identity (``references``, ``expr_types``, ``bindings``,
``cover_items``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any, Literal, overload

from osc2check.semantics.bindings import Binding, CoverItem
from osc2check.semantics.symbols import Namespace, Symbol, SymbolKind
from osc2check.semantics.types import Type
from osc2check.syntax import ast


@dataclass(frozen=True, slots=True)
class Context:
    """Where a declaration was written: its namespace and the namespaces it uses."""

    namespace: str = ""
    uses: tuple[str, ...] = ()


@dataclass(eq=False)
class Model:
    base: Model | None = None
    namespaces: dict[str, Namespace] = field(default_factory=dict)
    members: dict[Symbol, dict[str, list[Symbol]]] = field(default_factory=dict)
    behaviours: dict[Symbol | None, dict[str, list[Symbol]]] = field(default_factory=dict)
    modifiers: dict[Symbol | None, dict[str, list[Symbol]]] = field(default_factory=dict)
    units: dict[str, Symbol] = field(default_factory=dict)
    enum_members: dict[Symbol, list[Symbol]] = field(default_factory=dict)
    children: dict[Symbol, list[Symbol]] = field(default_factory=dict)  # direct subtypes
    symbols: list[Symbol] = field(default_factory=list)  # every declared symbol, in order
    declarations: dict[ast.Node, Symbol] = field(default_factory=dict)
    references: dict[ast.Name, Symbol] = field(default_factory=dict)
    expr_types: dict[ast.Node, Type] = field(default_factory=dict)
    bindings: dict[ast.Node, Binding] = field(default_factory=dict)  # call -> its arguments
    cover_items: dict[ast.CoverageDecl, CoverItem] = field(default_factory=dict)
    library_namespaces: set[str] = field(default_factory=set)  # library namespaces imported

    # ---- namespaces ------------------------------------------------------------

    @overload
    def namespace(self, name: str, create: Literal[True]) -> Namespace: ...
    @overload
    def namespace(self, name: str, create: bool = False) -> Namespace | None: ...
    def namespace(self, name: str, create: bool = False) -> Namespace | None:
        ns = self.namespaces.get(name)
        if ns is None and self.base is not None and name in self.base.namespaces:
            return self.base.namespaces[name] if not create else self._own_namespace(name)
        if ns is None and create:
            ns = self.namespaces[name] = Namespace(name)
        return ns

    def _own_namespace(self, name: str) -> Namespace:
        ns = self.namespaces.get(name)
        if ns is None:
            ns = self.namespaces[name] = Namespace(name)
        return ns

    def namespace_parts(self, name: str) -> list[Namespace]:
        """The library's and the program's parts of namespace ``name`` that are in reach."""
        parts = []
        if (
            self.base is not None
            and name in self.base.namespaces
            and (name == "" or name in self.library_namespaces)
        ):
            parts.append(self.base.namespaces[name])
        if name in self.namespaces:
            parts.append(self.namespaces[name])
        return parts

    def _own(self, ns: str, name: str) -> list[Symbol]:
        found: list[Symbol] = []
        for part in self.namespace_parts(ns):
            found.extend(part.symbols.get(name, ()))
        return found

    def _exported(self, ns: str, name: str, seen: set[str] | None = None) -> list[Symbol]:
        seen = seen if seen is not None else set()
        if ns in seen:
            return []
        seen.add(ns)
        found: list[Symbol] = []
        for part in self.namespace_parts(ns):
            if part.exports_all or name in part.exports:
                found.extend(part.symbols.get(name, ()))
            for other, only in part.reexports:
                if only is None or only == name:  # `other::*` and `other::name` reach
                    found.extend(self._own(other, name))  # what `other` has, exported or not
                    found.extend(self._exported(other, name, seen))
        return found

    def lookup(
        self,
        name: str,
        ctx: Context,
        qualifier: str | None = None,
        accept: Callable[[Symbol], bool] | None = None,
    ) -> list[Symbol]:
        """Global symbols named ``name`` visible from ``ctx`` (nearest first).

        ``ns::name`` finds what namespace ``ns`` declares or re-exports; export
        lists only matter to ``use`` (§7.7.4.1). An unprefixed name is looked up
        in the current namespace, then in every used namespace at once (§7.7.4.2:
        several same-named candidates there make the name ambiguous, see
        ``ambiguous``), then in the null namespace. ``accept`` keeps only the
        symbols of the wanted kind at each step.
        """

        def kept(symbols: list[Symbol]) -> list[Symbol]:
            unique = list({id(s): s for s in symbols}.values())
            return [s for s in unique if accept(s)] if accept is not None else unique

        if qualifier is not None:
            if qualifier == ctx.namespace or qualifier == "":
                return kept(self._own(qualifier, name))
            return kept(self._own(qualifier, name) + self._exported(qualifier, name))
        found = kept(self._own(ctx.namespace, name))
        if found:
            return found
        found = kept([s for used in ctx.uses for s in self._exported(used, name)])
        if found:
            return found
        if ctx.namespace:
            return kept(self._own("", name))
        return []

    @staticmethod
    def ambiguous(found: list[Symbol]) -> bool:
        """Whether a lookup's result names declarations of several namespaces."""
        return len({s.namespace for s in found}) > 1

    # ---- members, behaviours, modifiers ----------------------------------------

    @overload
    def _tables(
        self, attr: Literal["members"]
    ) -> Iterator[dict[Symbol, dict[str, list[Symbol]]]]: ...
    @overload
    def _tables(
        self, attr: Literal["behaviours", "modifiers"]
    ) -> Iterator[dict[Symbol | None, dict[str, list[Symbol]]]]: ...
    @overload
    def _tables(self, attr: Literal["enum_members"]) -> Iterator[dict[Symbol, list[Symbol]]]: ...
    @overload
    def _tables(self, attr: Literal["references"]) -> Iterator[dict[ast.Name, Symbol]]: ...
    @overload
    def _tables(self, attr: Literal["expr_types"]) -> Iterator[dict[ast.Node, Type]]: ...
    @overload
    def _tables(self, attr: Literal["bindings"]) -> Iterator[dict[ast.Node, Binding]]: ...
    @overload
    def _tables(
        self, attr: Literal["cover_items"]
    ) -> Iterator[dict[ast.CoverageDecl, CoverItem]]: ...
    def _tables(self, attr: str) -> Iterator[object]:
        model: Model | None = self
        while model is not None:
            yield getattr(model, attr)
            model = model.base

    def ancestors(self, symbol: Symbol | None) -> Iterator[Symbol]:
        """``symbol`` and its supertypes, nearest first (stops on cycles)."""
        seen: set[int] = set()
        while symbol is not None and id(symbol) not in seen:
            seen.add(id(symbol))
            yield symbol
            symbol = symbol.parent

    def own_members(self, owner: Symbol, name: str | None = None) -> list[Symbol]:
        """Members declared on ``owner`` itself (and by ``extend``), not inherited."""
        found: list[Symbol] = []
        for table in reversed(list(self._tables("members"))):
            members = table.get(owner)
            if not members:
                continue
            if name is None:
                for group in members.values():
                    found.extend(group)
            else:
                found.extend(members.get(name, ()))
        return found

    def member(self, owner: Symbol | None, name: str) -> list[Symbol]:
        """Members named ``name`` of ``owner`` or its supertypes, nearest first."""
        for sym in self.ancestors(owner):
            found = self.own_members(sym, name)
            if found:
                return found
        return []

    def all_members(self, owner: Symbol | None) -> list[Symbol]:
        """Every member of ``owner``, inherited ones first, in declaration order."""
        chain = list(self.ancestors(owner))
        result: list[Symbol] = []
        for sym in reversed(chain):
            result.extend(self.own_members(sym))
        return result

    def parameters(self, owner: Symbol | None) -> list[Symbol]:
        """Fields that are parameters (not variables, events or methods), in order."""
        return [m for m in self.all_members(owner) if m.kind is SymbolKind.FIELD]

    def _keyed(
        self, attr: Literal["behaviours", "modifiers"], key: Symbol | None, name: str | None
    ) -> list[Symbol]:
        found: list[Symbol] = []
        for table in self._tables(attr):
            entries = table.get(key)
            if not entries:
                continue
            if name is None:
                for group in entries.values():
                    found.extend(group)
            else:
                found.extend(entries.get(name, ()))
        return found

    def behaviour(self, actor: Symbol | None, name: str) -> list[Symbol]:
        """Scenarios and actions named ``name`` of ``actor`` or its supertypes."""
        if actor is None:
            return self._keyed("behaviours", None, name)
        for sym in self.ancestors(actor):
            found = self._keyed("behaviours", sym, name)
            if found:
                return found
        return []

    def behaviours_of(self, actor: Symbol | None) -> list[Symbol]:
        result: list[Symbol] = []
        for sym in self.ancestors(actor) if actor is not None else [None]:
            result.extend(self._keyed("behaviours", sym, None))
        return result

    def modifier(self, key: Symbol | None, name: str) -> list[Symbol]:
        """Modifiers named ``name`` associated with ``key`` (an actor or a behaviour)
        or with one of its supertypes; ``None`` for unassociated modifiers."""
        if key is None:
            return self._keyed("modifiers", None, name)
        for sym in self.ancestors(key):
            found = self._keyed("modifiers", sym, name)
            if found:
                return found
        return []

    def modifiers_of(self, key: Symbol | None) -> list[Symbol]:
        result: list[Symbol] = []
        for sym in self.ancestors(key) if key is not None else [None]:
            result.extend(self._keyed("modifiers", sym, None))
        return result

    def _unit_tables(self) -> list[dict[str, Symbol]]:
        tables = [self.units]
        if self.base is not None and "stdtypes" in self.library_namespaces:
            tables.append(self.base.units)
        return tables

    def unit(self, name: str) -> Symbol | None:
        """The unit named ``name`` (unit names are global; library units once imported)."""
        for table in self._unit_tables():
            if name in table:
                return table[name]
        return None

    def all_units(self) -> dict[str, Symbol]:
        result: dict[str, Symbol] = {}
        for table in reversed(self._unit_tables()):
            result.update(table)
        return result

    def enum_values(self, enum: Symbol) -> list[Symbol]:
        found: list[Symbol] = []
        for table in reversed(list(self._tables("enum_members"))):
            found.extend(table.get(enum, ()))
        return found

    def visible_enums(self, ctx: Context) -> Iterator[Symbol]:
        """Every enum visible from ``ctx`` without qualification."""
        spaces = [ctx.namespace, *ctx.uses]
        if ctx.namespace:
            spaces.append("")
        seen: set[int] = set()
        for ns in spaces:
            for part in self.namespace_parts(ns):
                for group in part.symbols.values():
                    for sym in group:
                        if sym.kind is SymbolKind.ENUM and id(sym) not in seen:
                            seen.add(id(sym))
                            yield sym

    def _first(self, attr: str, key: object) -> Any:
        """``key``'s entry in side table ``attr``, this program's or the library's."""
        for table in self._tables(attr):  # type: ignore[call-overload]
            if key in table:
                return table[key]
        return None

    def reference(self, name: ast.Name) -> Symbol | None:
        """What ``name`` refers to; names in the library resolve through the base model."""
        found: Symbol | None = self._first("references", name)
        return found

    def type_of(self, node: ast.Node) -> Type | None:
        """The type of an expression node, in this program or in the library."""
        found: Type | None = self._first("expr_types", node)
        return found

    def binding(self, call: ast.Node) -> Binding | None:
        """How the call checker bound the arguments of ``call`` (an invocation, modifier
        application, method or built-in call, ``emit`` or composition); None for a call
        it could not resolve. Calls in the library resolve through the base model."""
        found: Binding | None = self._first("bindings", call)
        return found

    def cover_item(self, decl: ast.CoverageDecl) -> CoverItem | None:
        """The ``cover``/``record`` item ``decl`` declares, as the checker read it."""
        found: CoverItem | None = self._first("cover_items", decl)
        return found

    def cover_items_of(self, owner: Symbol) -> list[CoverItem]:
        """The cover and record items of ``owner`` and its supertypes (``extend``
        included), inherited ones first, each in the order written."""
        result: list[CoverItem] = []
        for sym in reversed(list(self.ancestors(owner))):
            for table in reversed(list(self._tables("cover_items"))):
                result.extend(item for item in table.values() if item.owner is sym)
        return result
