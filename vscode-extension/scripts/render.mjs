// Render OSC2 source to HTML with the extension's TextMate grammar (the same
// tokenizer VS Code uses), for the README screenshot.
//
//   node scripts/render.mjs FILE.osc FIRST-LAST OUT.html
//   chromium --headless --no-sandbox --disable-gpu --disable-background-networking \
//     --disable-component-update --no-first-run --hide-scrollbars \
//     --window-size=980,760 --screenshot=images/highlighting.png OUT.html
//
// Colours: a dark palette in the spirit of VS Code's default dark theme,
// chosen per scope below.

import { readFileSync, writeFileSync } from "node:fs";
import { basename } from "node:path";
import { tokenize } from "./tokenize.mjs";

// Most specific prefix wins (longest match).
const PALETTE = {
  comment: "color:#6a9955;font-style:italic",
  string: "color:#ce9178",
  "constant.character.escape": "color:#d7ba7d",
  "constant.numeric": "color:#b5cea8",
  "constant.language": "color:#569cd6",
  "keyword.other.unit": "color:#4ec9b0;font-style:italic",
  "keyword.control": "color:#c586c0",
  "keyword.operator": "color:#d4d4d4",
  "keyword.operator.logical": "color:#569cd6",
  "keyword.operator.in": "color:#569cd6",
  "keyword.other": "color:#569cd6",
  storage: "color:#569cd6",
  "entity.name.type": "color:#4ec9b0",
  "entity.other.inherited-class": "color:#4ec9b0",
  "entity.name.namespace": "color:#4ec9b0",
  "entity.name.function": "color:#dcdcaa",
  "entity.name.label": "color:#c8c8c8;font-weight:bold",
  "support.function": "color:#dcdcaa",
  "support.type": "color:#4ec9b0",
  "variable.parameter": "color:#9cdcfe",
  "variable.other.member": "color:#9cdcfe",
  "variable.other.event": "color:#d7ba7d",
  "variable.other.enummember": "color:#4fc1ff",
  "variable.language": "color:#569cd6",
};

function style(scopes) {
  let best = "";
  let bestLength = -1;
  for (const scope of scopes) {
    for (const [prefix, css] of Object.entries(PALETTE)) {
      if ((scope === prefix || scope.startsWith(prefix + ".")) && prefix.length >= bestLength) {
        best = css;
        bestLength = prefix.length;
      }
    }
  }
  return best;
}

const escape = (s) => s.replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;");

const [file, range, out] = process.argv.slice(2);
if (!file || !range || !out) {
  console.error("usage: node scripts/render.mjs FILE.osc FIRST-LAST OUT.html");
  process.exit(2);
}
const [first, last] = range.split("-").map(Number);
const lines = (await tokenize(readFileSync(file, "utf8"))).slice(first - 1, last);
const body = lines
  .map((tokens, i) => {
    const code = tokens.map((t) => {
      const css = style(t.scopes);
      return css ? `<span style="${css}">${escape(t.text)}</span>` : escape(t.text);
    });
    return `<span class="n">${first + i}</span>${code.join("")}`;
  })
  .join("\n");

writeFileSync(
  out,
  `<!doctype html><meta charset="utf-8"><title>${escape(basename(file))}</title>
<style>
  body { margin: 0; background: #1f1f1f; }
  .tab { font: 13px system-ui, sans-serif; color: #ccc; background: #181818; padding: 8px 16px; border-bottom: 1px solid #2b2b2b; }
  pre { margin: 0; padding: 12px 0; color: #d4d4d4; font: 14px/20px "DejaVu Sans Mono", monospace; }
  .n { display: inline-block; width: 44px; padding-right: 18px; text-align: right; color: #6e7681; }
</style>
<div class="tab">${escape(basename(file))}</div>
<pre>${body}</pre>
`,
);
console.log(`wrote ${out} (${lines.length} lines)`);
