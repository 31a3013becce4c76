// Tokenize OSC2 text with the extension's TextMate grammar, the way VS Code
// does (vscode-textmate + vscode-oniguruma).
//
//   node scripts/tokenize.mjs FILE.osc     print each token with its scopes
//
// Also imported by scripts/render.mjs and the unit tests.

import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const require = createRequire(import.meta.url);
const textmate = require("vscode-textmate");
const oniguruma = require("vscode-oniguruma");

const here = dirname(fileURLToPath(import.meta.url));
export const GRAMMAR_PATH = join(here, "..", "syntaxes", "osc2.tmLanguage.json");

let grammarPromise;

/** Load the grammar once. */
export function loadGrammar() {
  if (!grammarPromise) {
    grammarPromise = (async () => {
      const wasm = readFileSync(require.resolve("vscode-oniguruma/release/onig.wasm"));
      await oniguruma.loadWASM(wasm.buffer.slice(wasm.byteOffset, wasm.byteOffset + wasm.byteLength));
      const registry = new textmate.Registry({
        onigLib: Promise.resolve({
          createOnigScanner: (patterns) => new oniguruma.OnigScanner(patterns),
          createOnigString: (s) => new oniguruma.OnigString(s),
        }),
        loadGrammar: async (scopeName) =>
          scopeName === "source.osc2"
            ? textmate.parseRawGrammar(readFileSync(GRAMMAR_PATH, "utf8"), GRAMMAR_PATH)
            : null,
      });
      return registry.loadGrammar("source.osc2");
    })();
  }
  return grammarPromise;
}

/**
 * Tokenize text. Returns one array per line of {text, scopes} tokens
 * (scopes without the root scope "source.osc2").
 */
export async function tokenize(text) {
  const grammar = await loadGrammar();
  let state = textmate.INITIAL;
  const lines = text.replace(/\r\n?/g, "\n").split("\n");
  return lines.map((line) => {
    const result = grammar.tokenizeLine(line, state);
    state = result.ruleStack;
    return result.tokens.map((t) => ({
      text: line.slice(t.startIndex, t.endIndex),
      scopes: t.scopes.slice(1),
    }));
  });
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
  const file = process.argv[2];
  if (!file) {
    console.error("usage: node scripts/tokenize.mjs FILE.osc");
    process.exit(2);
  }
  const lines = await tokenize(readFileSync(file, "utf8"));
  lines.forEach((tokens, i) => {
    for (const t of tokens) {
      if (t.text.trim() === "") continue;
      console.log(`${String(i + 1).padStart(4)}  ${JSON.stringify(t.text).padEnd(28)} ${t.scopes.join(" ")}`);
    }
  });
}
