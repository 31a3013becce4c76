"""What is visible at a position: the chain of AST nodes down to it, and its scope.

The resolver keeps no scopes after the analysis (only ``references`` and
``expr_types``), so the scope at a position is rebuilt from the enclosing nodes
with the resolver's own rules (``scope.declaration_scope`` for a declaration's
body): the declaration that owns the members (``owner``), what ``it`` means,
the labels, method parameters and event bindings in reach. The language server
asks this module instead of knowing scope rules itself.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

from osc2check.semantics.model import Context, Model
from osc2check.semantics.scope import Scope, declaration_scope
from osc2check.semantics.symbols import Symbol
from osc2check.syntax import ast
from osc2check.syntax.walk import children


def extent(node: ast.Node) -> int:
    """The end offset of ``node`` including all its descendants.

    A node's span normally covers its children; after error recovery (and in
    parsers older than the fix that made calls' spans include their
    arguments) the last child may reach further, so this follows the last
    child down.
    """
    end = node.span.end
    last = _last_child(node)
    while last is not None:
        end = max(end, last.span.end)
        last = _last_child(last)
    return end


def _last_child(node: ast.Node) -> ast.Node | None:
    found = None
    for child in children(node):
        found = child
    return found


def node_path(root: ast.Node, offset: int) -> list[ast.Node]:
    """The nodes from ``root`` down to the innermost one that contains ``offset``.

    A cursor just after a node still counts as inside it, unless the next
    sibling starts there.
    """
    path = [root]
    node = root
    while True:
        best = None
        for child in children(node):
            span = child.span
            if span.start > offset:
                break
            end = span.end if span.end > offset else extent(child)
            if span.start <= offset < end:
                best = child
                break
            if end == offset and best is None:
                best = child
        if best is None:
            return path
        path.append(best)
        node = best


def innermost(
    path: list[ast.Node], kinds: type[ast.Node] | tuple[type[ast.Node], ...]
) -> ast.Node | None:
    for node in reversed(path):
        if isinstance(node, kinds):
            return node
    return None


def scope_at(model: Model, path: list[ast.Node]) -> Scope:
    """Rebuild the scope of the innermost node of ``path``."""
    scope = Scope(Context())
    for i, node in enumerate(path):
        inner = path[i + 1] if i + 1 < len(path) else None
        match node:
            case ast.StructuredDecl() | ast.ExtendDecl():
                owner = model.declarations.get(node)
                if owner is not None:
                    context = owner.context if isinstance(owner.context, Context) else Context()
                    scope = declaration_scope(owner, context)
            case ast.GlobalDecl():
                sym = model.references.get(node.field.names[0]) if node.field.names else None
                if sym is not None and isinstance(sym.context, Context):
                    scope.context = sym.context
            case ast.FieldDecl():
                if inner is not None and any(inner is w for w in node.with_members):
                    sym = model.references.get(node.names[0]) if node.names else None
                    scope.it = sym.type if sym is not None else None
                    scope.behaviour = None
                    scope.modifier_block = False
            case ast.Invocation():
                if inner is not None and any(inner is w for w in node.with_members):
                    target = model.references.get(node.name)
                    if target is not None and target.kind.is_behaviour:
                        scope.it = target.type
                        scope.behaviour = target
                        if node.actor is not None:
                            actor_type = model.expr_types.get(node.actor)
                            if actor_type is not None and actor_type.symbol is not None:
                                scope.actor = actor_type.symbol
                    else:
                        scope.it = None
                        scope.behaviour = target
                    scope.modifier_block = True
            case ast.Composition():
                if inner is not None and any(inner is w for w in node.with_members):
                    scope.it = None
                    scope.behaviour = None
                    scope.modifier_block = True
            case ast.DoDirective():
                for member in _do_members(node.member):
                    if member.label is not None and member.label.text:
                        sym = model.references.get(member.label)
                        if sym is not None:
                            scope.locals[member.label.text] = sym
            case ast.MethodDecl() | ast.EventDecl():
                sym = model.declarations.get(node)
                if sym is not None:
                    for param in sym.parameters:
                        scope.locals[param.name] = param
            case ast.EventReference():
                if node.alias is not None and node.alias.text:
                    sym = model.references.get(node.alias)
                    if sym is not None:
                        scope.locals[node.alias.text] = sym
    return scope


def _do_members(member: ast.DoMember) -> Iterator[ast.DoMember]:
    yield member
    body = member.body
    if isinstance(body, ast.Composition):
        for inner in body.members:
            yield from _do_members(inner)


def visible_globals(
    model: Model, ctx: Context, accept: Callable[[Symbol], bool] | None = None
) -> list[Symbol]:
    """Global symbols visible without qualification from ``ctx``."""
    seen: set[int] = set()
    found: list[Symbol] = []
    for ns in dict.fromkeys([ctx.namespace, *ctx.uses, ""]):
        for part in model.namespace_parts(ns):
            exported_only = ns != ctx.namespace and ns != ""
            for name, group in part.symbols.items():
                if exported_only and not (part.exports_all or name in part.exports):
                    continue
                for sym in group:
                    if id(sym) not in seen and (accept is None or accept(sym)):
                        seen.add(id(sym))
                        found.append(sym)
    return found
