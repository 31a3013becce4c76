"""OSC2 text of expressions and a behaviour's display name, e.g. ``hero.drive() [34]``,
so that ``py_trees.display.unicode_tree`` shows the scenario as written."""

from __future__ import annotations

from osc2check.syntax import ast

__all__ = ["node_name", "unparse"]


def node_name(text: str, node: ast.Node) -> str:
    """``text [line]``: a behaviour's display name."""
    return f"{text} [{node.span.line}]"


def unparse(node: ast.Node | None) -> str:
    """OSC2 text of an expression, argument or event spec (for display names)."""
    match node:
        case None:
            return ""
        case ast.IntLiteral() | ast.FloatLiteral():
            return node.text
        case ast.PhysicalLiteral():
            return f"{node.number_text}{node.unit.text}"
        case ast.StringLiteral():
            return f'"{node.value}"'
        case ast.BoolLiteral():
            return "true" if node.value else "false"
        case ast.NameRef():
            return str(node.name)
        case ast.EnumRef():
            return f"{node.enum}!{node.member.text}"
        case ast.MemberAccess():
            return f"{unparse(node.target)}.{node.member.text}"
        case ast.Call():
            return f"{unparse(node.callee)}({', '.join(unparse(a) for a in node.arguments)})"
        case ast.Index():
            return f"{unparse(node.target)}[{unparse(node.index)}]"
        case ast.Unary():
            return (
                f"not {unparse(node.operand)}"
                if node.op == "not"
                else f"{node.op}{unparse(node.operand)}"
            )
        case ast.Binary():
            return f"{unparse(node.left)} {node.op} {unparse(node.right)}"
        case ast.Ternary():
            return f"{unparse(node.condition)} ? {unparse(node.then)} : {unparse(node.otherwise)}"
        case ast.ListLiteral():
            return f"[{', '.join(unparse(i) for i in node.items)}]"
        case ast.RangeLiteral():
            return f"[{unparse(node.low)}..{unparse(node.high)}]"
        case ast.PositionalArgument():
            return unparse(node.value)
        case ast.NamedArgument():
            return f"{node.name.text}: {unparse(node.value)}"
        case ast.EventArgument():
            return "@" + ".".join(p.text for p in node.path)
        case ast.EventReference():
            text = "@" + ".".join(p.text for p in node.path)
            if node.alias is not None:
                text += f" as {node.alias.text}"
            if node.condition is not None:
                text += f" if {unparse(node.condition)}"
            return text
        case ast.EventCondition():
            return unparse(node.expr)
        case ast.Emit():
            args = ", ".join(unparse(a) for a in node.arguments)
            return f"emit {node.event.text}" + (f"({args})" if node.arguments else "")
    return type(node).__name__
