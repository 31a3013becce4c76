// Source of the TextMate grammar syntaxes/osc2.tmLanguage.json.
//
// The grammar is written here in JavaScript so that the identifier and
// qualified-name sub-expressions are defined once. Run `npm run grammar` after
// editing; `npm run test:unit` fails when the committed JSON is out of date.
//
//   node scripts/grammar.mjs           write syntaxes/osc2.tmLanguage.json
//   node scripts/grammar.mjs --check   exit 1 if the committed file differs

import { readFileSync, writeFileSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const r = String.raw;

// ---------------------------------------------------------------- lexical pieces
// Identifier: a Unicode letter or `_`, then letters, digits, `_`; or any text
// between bars (`|foot/s|`).
const PLAIN_ID = r`[^\W\d]\w*`;
const BAR_ID = r`\|[^|\n]+\|`;
const ID = `(?:${PLAIN_ID}|${BAR_ID})`;
// Qualified name: a.b.c, ns::name, ::name.
const QNAME = `(?:::)?${ID}(?:(?:\\.|::)${ID})*`;
// A number may carry a sign unless it directly follows an operand.
const NUM_START = r`(?<![\w)\]|])`;
const EXP = r`(?:[eE][+-]?\d+)`;
const UNIT = `(${PLAIN_ID}|${BAR_ID})?`;

const PRIMITIVE = r`\b(?:bool|int|uint|float|string)\b`;
const COMPOSITIONS = ["serial", "parallel", "one_of"];
// Words after which a `:` opens a block rather than ending a field name.
const BLOCK_WORDS = ["with", "do", "on", ...COMPOSITIONS];

const words = (list) => list.join("|");

// keyword -> scope prefix. Each keyword gets scope `<prefix>.<keyword>.osc2`.
// `actor` is absent: outside a declaration it is the implicit name (variable.language.actor).
const STORAGE_TYPES = [
  "type", "unit", "enum", "struct", "scenario", "action", "modifier",
  "extend", "def", "var", "event", "list", "range",
];
const OTHER_KEYWORDS = [
  "namespace", "use", "export", "inherits", "of", "is", "SI", "factor", "offset",
  "keep", "default", "hard", "remove_default", "cover", "record", "expression",
  "undefined", "external", "only", "with", "as",
];
const BEHAVIOUR_KEYWORDS = [
  "do", "serial", "parallel", "one_of", "wait", "emit", "until", "on", "call",
  "rise", "fall", "elapsed", "every", "sample",
];
const BUILTIN_METHODS = [
  "as", "is", "size", "filter", "first_index", "count", "has", "map", "lower", "upper",
];

const scopeName = (prefix, word) => `${prefix}.${word.toLowerCase()}.osc2`;

function keywordRules(list, prefix) {
  // One rule per group; the scope names the keyword (keyword.control.wait.osc2 …).
  // A keyword right after `.` is a member name (it.unit, x.event), never a keyword.
  const lower = list.filter((w) => w === w.toLowerCase());
  const rules = [{ match: `(?<![.\\w])(${words(lower)})\\b`, name: `${prefix}.$1.osc2` }];
  for (const w of list.filter((w) => w !== w.toLowerCase())) {
    rules.push({ match: `(?<![.\\w])${w}\\b`, name: scopeName(prefix, w) });
  }
  return rules;
}

const typeRef = {
  patterns: [
    { match: PRIMITIVE, name: "support.type.primitive.osc2" },
    { match: r`\b(list|range)\s+(of)\b`, captures: { 1: { name: "storage.type.$1.osc2" }, 2: { name: "keyword.other.of.osc2" } } },
    { include: "#qualified-type-name" },
  ],
};

// ---------------------------------------------------------------- repository
const repository = {
  comment: {
    match: r`(#).*$`,
    name: "comment.line.number-sign.osc2",
    captures: { 1: { name: "punctuation.definition.comment.osc2" } },
  },

  "line-continuation": {
    match: r`\\(?=\s*$)`,
    name: "punctuation.separator.continuation.line.osc2",
  },

  "qualified-type-name": {
    // The parts of a qualified name that name a type; `::`/`.` stay operators.
    patterns: [
      { match: "::", name: "keyword.operator.namespace.osc2" },
      { match: r`\.`, name: "punctuation.accessor.osc2" },
      { match: ID, name: "entity.name.type.osc2" },
    ],
  },

  // ------------------------------------------------------------ strings
  string: {
    patterns: [
      {
        begin: `"""`, end: `"""`, name: "string.quoted.triple.double.osc2",
        beginCaptures: { 0: { name: "punctuation.definition.string.begin.osc2" } },
        endCaptures: { 0: { name: "punctuation.definition.string.end.osc2" } },
        patterns: [{ include: "#string-escape" }],
      },
      {
        begin: `'''`, end: `'''`, name: "string.quoted.triple.single.osc2",
        beginCaptures: { 0: { name: "punctuation.definition.string.begin.osc2" } },
        endCaptures: { 0: { name: "punctuation.definition.string.end.osc2" } },
        patterns: [{ include: "#string-escape" }],
      },
      {
        // Single-line strings end at the closing quote or, unterminated, at the end of the line.
        begin: `"`, end: `(")|$`, name: "string.quoted.double.osc2",
        beginCaptures: { 0: { name: "punctuation.definition.string.begin.osc2" } },
        endCaptures: { 1: { name: "punctuation.definition.string.end.osc2" } },
        patterns: [{ include: "#string-escape" }],
      },
      {
        begin: `'`, end: `(')|$`, name: "string.quoted.single.osc2",
        beginCaptures: { 0: { name: "punctuation.definition.string.begin.osc2" } },
        endCaptures: { 1: { name: "punctuation.definition.string.end.osc2" } },
        patterns: [{ include: "#string-escape" }],
      },
    ],
  },
  "string-escape": {
    match: r`\\(?:x\h{2}|u\h{4}|U\h{8}|.|$)`,
    name: "constant.character.escape.osc2",
  },

  // ------------------------------------------------------------ numbers
  // A physical literal is a number immediately followed by a unit name:
  // 10kph, 3.5m, 1e3m, 15|foot/s|. The number and the unit are scoped apart.
  number: {
    patterns: [
      {
        match: `${NUM_START}([+-]?0[xX]\\h+)${UNIT}`,
        captures: {
          1: { name: "constant.numeric.integer.hexadecimal.osc2" },
          2: { name: "keyword.other.unit.osc2" },
        },
      },
      {
        match: `${NUM_START}([+-]?(?:\\d+\\.\\d+${EXP}?|\\.\\d+${EXP}?|\\d+${EXP}))${UNIT}`,
        captures: {
          1: { name: "constant.numeric.float.osc2" },
          2: { name: "keyword.other.unit.osc2" },
        },
      },
      {
        match: `${NUM_START}([+-]?\\d+)${UNIT}`,
        captures: {
          1: { name: "constant.numeric.integer.decimal.osc2" },
          2: { name: "keyword.other.unit.osc2" },
        },
      },
      {
        match: `${NUM_START}[+-]?\\b(?:inf|nan)\\b`,
        name: "constant.numeric.float.osc2",
      },
    ],
  },

  // ------------------------------------------------------------ names
  "event-reference": {
    // @name, @a.b — the event path after `@`.
    match: `(@)(${QNAME})`,
    captures: {
      1: { name: "punctuation.definition.event.osc2" },
      2: { name: "variable.other.event.osc2" },
    },
  },
  "enum-reference": {
    // T!member (but not a != b)
    match: `(${ID})(!)(?!=)(${ID})`,
    captures: {
      1: { name: "entity.name.type.enum.osc2" },
      2: { name: "keyword.operator.enum.osc2" },
      3: { name: "variable.other.enummember.osc2" },
    },
  },
  "language-constant": {
    patterns: [
      { match: r`(?<![.\w])(?:true|false)\b`, name: "constant.language.boolean.osc2" },
      { match: r`(?<![.\w])it\b`, name: "variable.language.it.osc2" },
      { match: r`(?<![.\w])actor\b`, name: "variable.language.actor.osc2" },
      { match: `(?<![.\\w])${PRIMITIVE.slice(2)}`, name: "support.type.primitive.osc2" },
    ],
  },
  "emit-statement": {
    // emit name — the event being emitted.
    match: `(?<![.\\w])(emit)\\s+(${QNAME})`,
    captures: {
      1: { name: "keyword.control.emit.osc2" },
      2: { name: "variable.other.event.osc2" },
    },
  },
  "return-type": {
    match: `(->)\\s*((?:(?:list|range)\\s+of\\s+)?${QNAME})`,
    captures: {
      1: { name: "keyword.operator.arrow.osc2" },
      2: typeRef,
    },
  },
  "builtin-method": {
    // .as(T), .size(), .filter(…), … and the range(a, b) / override(…) built-ins
    patterns: [
      { match: `(?<=\\.)(?:${words(BUILTIN_METHODS)})(?=\\s*\\()`, name: "support.function.builtin.osc2" },
      { match: r`(?<![.\w])(?:range|override)(?=\s*\()`, name: "support.function.builtin.osc2" },
    ],
  },
  keyword: {
    patterns: [
      { match: r`(?<![.\w])import\b`, name: "keyword.control.import.osc2" },
      { match: r`(?<![.\w])if\b`, name: "keyword.control.conditional.if.osc2" },
      { match: r`(?<![.\w])global\b`, name: "storage.modifier.global.osc2" },
      ...keywordRules(BEHAVIOUR_KEYWORDS, "keyword.control"),
      ...keywordRules(STORAGE_TYPES, "storage.type"),
      ...keywordRules(OTHER_KEYWORDS, "keyword.other"),
    ],
  },
  call: {
    // name( … ) — an invocation of an action, scenario, modifier or method.
    match: `(${ID})(?=\\s*\\()`,
    captures: { 1: { name: "entity.name.function.call.osc2" } },
  },
  "quoted-identifier": {
    match: BAR_ID,
    name: "variable.other.quoted.osc2",
  },

  // ------------------------------------------------------------ operators
  "word-operator": {
    // and, or, not, in — before #call so that `not (…)` stays an operator.
    patterns: [
      { match: r`(?<![.\w])(?:and|or|not)\b`, name: "keyword.operator.logical.osc2" },
      { match: r`(?<![.\w])in\b`, name: "keyword.operator.in.osc2" },
    ],
  },
  operator: {
    patterns: [
      { match: "=>", name: "keyword.operator.logical.implication.osc2" },
      { match: "->", name: "keyword.operator.arrow.osc2" },
      { match: "==|!=|<=|>=|<|>", name: "keyword.operator.comparison.osc2" },
      { match: "=", name: "keyword.operator.assignment.osc2" },
      { match: r`\.\.`, name: "keyword.operator.range.osc2" },
      { match: "::", name: "keyword.operator.namespace.osc2" },
      { match: "!", name: "keyword.operator.enum.osc2" },
      { match: r`[-+*/%]`, name: "keyword.operator.arithmetic.osc2" },
      { match: r`\.`, name: "punctuation.accessor.osc2" },
      { match: ",", name: "punctuation.separator.comma.osc2" },
      { match: ":", name: "punctuation.separator.colon.osc2" },
    ],
  },
  ternary: {
    // cond ? a : b — the `:` belonging to a `?` on the same line is an operator.
    begin: r`\?`,
    end: r`(:)(?!:)|$`,
    beginCaptures: { 0: { name: "keyword.operator.ternary.osc2" } },
    endCaptures: { 1: { name: "keyword.operator.ternary.osc2" } },
    patterns: [{ include: "#expression" }],
  },

  // ------------------------------------------------------------ bracketed regions
  "si-specification": {
    // SI(m: 1, s: -1, factor: 0.27, offset: 0): base units and factor/offset
    begin: r`(?<![.\w])(SI)\s*(\()`,
    end: r`\)`,
    beginCaptures: {
      1: { name: "keyword.other.si.osc2" },
      2: { name: "punctuation.section.parens.begin.osc2" },
    },
    endCaptures: { 0: { name: "punctuation.section.parens.end.osc2" } },
    patterns: [
      { include: "#comment" },
      {
        match: r`(?<![.\w])(factor|offset)\s*(:)(?!:)`,
        captures: {
          1: { name: "keyword.other.$1.osc2" },
          2: { name: "punctuation.separator.colon.osc2" },
        },
      },
      {
        match: r`(?<![.\w])(m|kg|s|A|K|mol|cd|rad)\s*(:)(?!:)`,
        captures: {
          1: { name: "keyword.other.unit.osc2" },
          2: { name: "punctuation.separator.colon.osc2" },
        },
      },
      { include: "#expression" },
    ],
  },
  arguments: {
    // ( … ): argument and parameter lists, parenthesised expressions.
    begin: r`\(`,
    end: r`\)`,
    beginCaptures: { 0: { name: "punctuation.section.parens.begin.osc2" } },
    endCaptures: { 0: { name: "punctuation.section.parens.end.osc2" } },
    patterns: [
      { include: "#comment" },
      { include: "#named-argument" },
      { include: "#expression" },
    ],
  },
  "named-argument": {
    // name: value — directly after `(` or `,`, or first on a continuation line.
    match: `(?:(?<=[(,])|^)\\s*(${ID})\\s*(:)(?!:)`,
    captures: {
      1: { name: "variable.parameter.osc2" },
      2: { name: "punctuation.separator.colon.osc2" },
    },
  },
  brackets: {
    // [a, b], [1..5]
    begin: r`\[`,
    end: r`\]`,
    beginCaptures: { 0: { name: "punctuation.section.brackets.begin.osc2" } },
    endCaptures: { 0: { name: "punctuation.section.brackets.end.osc2" } },
    patterns: [{ include: "#comment" }, { include: "#expression" }],
  },

  expression: {
    patterns: [
      { include: "#comment" },
      { include: "#line-continuation" },
      { include: "#string" },
      { include: "#si-specification" },
      { include: "#number" },
      { include: "#event-reference" },
      { include: "#enum-reference" },
      { include: "#emit-statement" },
      { include: "#return-type" },
      { include: "#builtin-method" },
      { include: "#keyword" },
      { include: "#language-constant" },
      { include: "#word-operator" },
      { include: "#call" },
      { include: "#quoted-identifier" },
      { include: "#ternary" },
      { include: "#arguments" },
      { include: "#brackets" },
      { include: "#operator" },
    ],
  },

  // ------------------------------------------------------------ declarations
  declaration: {
    patterns: [
      ...["scenario", "action", "actor", "struct"].map((kind) => ({
        // scenario vehicle.cut_in inherits base(cond == x):
        match: `^\\s*(${kind})\\s+(${QNAME})(?:\\s+(inherits)\\s+(${QNAME}))?`,
        captures: {
          1: { name: `storage.type.${kind}.osc2` },
          2: { name: `entity.name.type.${kind}.osc2` },
          3: { name: "keyword.other.inherits.osc2" },
          4: { name: "entity.other.inherited-class.osc2" },
        },
      })),
      {
        // modifier vehicle.speed_up of vehicle.drive
        match: `^\\s*(modifier)\\s+(${QNAME})(?:\\s+(of)\\s+(${QNAME}))?`,
        captures: {
          1: { name: "storage.type.modifier.osc2" },
          2: { name: "entity.name.type.modifier.osc2" },
          3: { name: "keyword.other.of.osc2" },
          4: { name: "entity.name.type.osc2" },
        },
      },
      {
        // enum colour: [red, green = 4, blue]  /  extend colour: [violet]
        begin: `^\\s*(enum|extend)\\s+(${QNAME})\\s*(:)\\s*(\\[)`,
        end: r`\]`,
        beginCaptures: {
          1: { name: "storage.type.$1.osc2" },
          2: { name: "entity.name.type.enum.osc2" },
          3: { name: "punctuation.separator.colon.osc2" },
          4: { name: "punctuation.section.brackets.begin.osc2" },
        },
        endCaptures: { 0: { name: "punctuation.section.brackets.end.osc2" } },
        patterns: [
          { include: "#comment" },
          { include: "#line-continuation" },
          { include: "#number" },
          { match: ID, name: "variable.other.enummember.osc2" },
          { match: "=", name: "keyword.operator.assignment.osc2" },
          { match: ",", name: "punctuation.separator.comma.osc2" },
        ],
      },
      {
        match: `^\\s*(enum)\\s+(${QNAME})`,
        captures: {
          1: { name: "storage.type.enum.osc2" },
          2: { name: "entity.name.type.enum.osc2" },
        },
      },
      {
        match: `^\\s*(extend)\\s+(${QNAME})`,
        captures: {
          1: { name: "storage.type.extend.osc2" },
          2: { name: "entity.name.type.osc2" },
        },
      },
      {
        // type speed is SI(m: 1, s: -1)
        match: `^\\s*(type)\\s+(${ID})`,
        captures: {
          1: { name: "storage.type.type.osc2" },
          2: { name: "entity.name.type.osc2" },
        },
      },
      {
        // unit kph of speed is SI(…)
        match: `^\\s*(unit)\\s+(${ID})(?:\\s+(of)\\s+(${QNAME}))?`,
        captures: {
          1: { name: "storage.type.unit.osc2" },
          2: { name: "entity.name.type.unit.osc2" },
          3: { name: "keyword.other.of.osc2" },
          4: { name: "entity.name.type.osc2" },
        },
      },
      {
        // def distance_to(other: actor) -> length is expression …
        match: `^\\s*(def)\\s+(${ID})`,
        captures: {
          1: { name: "storage.type.def.osc2" },
          2: { name: "entity.name.function.osc2" },
        },
      },
      {
        // event too_close(limit: length) is @x if cond
        match: `^\\s*(event)\\s+(${ID})`,
        captures: {
          1: { name: "storage.type.event.osc2" },
          2: { name: "variable.other.event.osc2" },
        },
      },
      {
        // namespace demo [use other]  /  namespace null
        match: `^\\s*(namespace)\\s+(?:(null)\\b|(${QNAME}))`,
        captures: {
          1: { name: "keyword.other.namespace.osc2" },
          2: { name: "constant.language.null.osc2" },
          3: { name: "entity.name.namespace.osc2" },
        },
      },
      {
        // import osc.standard  (import "file.osc" is a keyword plus a string)
        match: `^\\s*(import)\\s+(${QNAME})`,
        captures: {
          1: { name: "keyword.control.import.osc2" },
          2: { name: "entity.name.namespace.osc2" },
        },
      },
      {
        // use std.stdtypes, other
        match: `(?<![.\\w])(use)\\s+(${QNAME})`,
        captures: {
          1: { name: "keyword.other.use.osc2" },
          2: { name: "entity.name.namespace.osc2" },
        },
      },
    ],
  },

  member: {
    // Field declaration at the start of a member line:
    //   [var|global] name[, name]*: [list of] Type [= default] [with:]
    match:
      `^\\s*(?:(var|global)\\s+)?` +
      `(?!(?:${words(BLOCK_WORDS)})\\s*:)` +
      `(${ID}(?:\\s*,\\s*${ID})*)\\s*(:)(?!:)` +
      `(?:\\s*((?:(?:list|range)\\s+of\\s+)?${QNAME})(?=\\s*(?:$|=|#|\\\\|with\\b)))?`,
    captures: {
      1: { patterns: [{ match: "var", name: "storage.type.var.osc2" }, { match: "global", name: "storage.modifier.global.osc2" }] },
      2: {
        patterns: [
          { match: ID, name: "variable.other.member.osc2" },
          { match: ",", name: "punctuation.separator.comma.osc2" },
        ],
      },
      3: { name: "punctuation.separator.colon.osc2" },
      4: typeRef,
    },
  },

  // ------------------------------------------------------------ behaviour
  "do-block": {
    // do [label:] member — the block lasts while lines are indented deeper than `do`.
    begin: `^([ \\t]*)(do)\\b(?:\\s+(?!(?:${words(COMPOSITIONS)})\\b)(${ID})\\s*(:)(?!:))?`,
    while: r`^(?=\1[ \t]+\S|[ \t]*(?:#|$))`,
    name: "meta.block.do.osc2",
    beginCaptures: {
      2: { name: "keyword.control.do.osc2" },
      3: { name: "entity.name.label.osc2" },
      4: { name: "punctuation.separator.colon.osc2" },
    },
    patterns: [
      { include: "#comment" },
      { include: "#label" },
      { include: "#expression" },
    ],
  },
  label: {
    // label: serial:  /  label: actor.drive()   (inside a do block)
    match: `^\\s*(?!(?:${words(BLOCK_WORDS)})\\b)(${ID})\\s*(:)(?!:)`,
    captures: {
      1: { name: "entity.name.label.osc2" },
      2: { name: "punctuation.separator.colon.osc2" },
    },
  },
};

const grammar = {
  $schema: "https://raw.githubusercontent.com/martinring/tmlanguage/master/tmlanguage.json",
  name: "OpenSCENARIO DSL",
  scopeName: "source.osc2",
  fileTypes: ["osc"],
  comment: "Generated by scripts/grammar.mjs — edit that file, then run `npm run grammar`.",
  patterns: [
    { include: "#comment" },
    { include: "#do-block" },
    { include: "#declaration" },
    { include: "#member" },
    { include: "#expression" },
  ],
  repository,
};

const here = dirname(fileURLToPath(import.meta.url));
const target = join(here, "..", "syntaxes", "osc2.tmLanguage.json");
const text = JSON.stringify(grammar, null, 2) + "\n";

if (process.argv.includes("--check")) {
  let current = "";
  try {
    current = readFileSync(target, "utf8");
  } catch {
    // missing file is reported below
  }
  if (current !== text) {
    console.error("syntaxes/osc2.tmLanguage.json is out of date: run `npm run grammar`");
    process.exit(1);
  }
  console.log("syntaxes/osc2.tmLanguage.json is up to date");
} else {
  writeFileSync(target, text);
  console.log(`wrote ${target}`);
}
