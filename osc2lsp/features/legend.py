"""The semantic token legend (kept apart so the server can declare it without
importing the analysis)."""

TOKEN_TYPES = [
    "namespace",
    "type",
    "class",
    "enum",
    "struct",
    "function",
    "method",
    "property",
    "parameter",
    "variable",
    "enumMember",
    "event",
    "decorator",
    "label",
    "number",
    "unit",
]
TOKEN_MODIFIERS = ["declaration", "readonly", "defaultLibrary"]
