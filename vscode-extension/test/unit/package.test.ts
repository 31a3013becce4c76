// The extension's static parts: package.json contributions, the TextMate
// grammar (up to date, every scope asserted by a grammar test) and the
// language configuration.

import assert = require("node:assert/strict");
import { spawnSync } from "child_process";
import * as fs from "fs";
import * as path from "path";
import { describe, it } from "node:test";
import { fromRoot } from "./helpers/paths";

const manifest = JSON.parse(fs.readFileSync(fromRoot("package.json"), "utf8"));
const grammarFile = fromRoot("syntaxes", "osc2.tmLanguage.json");
const grammar = JSON.parse(fs.readFileSync(grammarFile, "utf8"));
const languageConfiguration = JSON.parse(fs.readFileSync(fromRoot("language-configuration.json"), "utf8"));

describe("package.json", () => {
  it("identifies the extension", () => {
    assert.equal(manifest.name, "osc2");
    assert.equal(manifest.publisher, "osc2-toolkit");
    assert.equal(manifest.version, "0.1.0");
    assert.equal(manifest.license, "Apache-2.0");
    assert.equal(manifest.main, "./dist/extension.js");
    assert.ok(fs.existsSync(fromRoot("LICENSE")), "LICENSE file");
    assert.ok(fs.existsSync(fromRoot("README.md")), "README.md");
  });

  it("requires a VS Code that vscode-languageclient supports", () => {
    const client = JSON.parse(fs.readFileSync(fromRoot("node_modules", "vscode-languageclient", "package.json"), "utf8"));
    assert.equal(manifest.engines.vscode, client.engines.vscode);
    assert.equal(manifest.devDependencies["@types/vscode"], manifest.engines.vscode.replace(/^\^/, ""));
  });

  it("contributes the osc2 language for *.osc with its configuration", () => {
    const [language] = manifest.contributes.languages;
    assert.equal(language.id, "osc2");
    assert.deepEqual(language.extensions, [".osc"]);
    assert.ok(fs.existsSync(fromRoot(language.configuration)));
    assert.deepEqual(manifest.activationEvents, ["onLanguage:osc2"]);
  });

  it("contributes the grammar under the scope the grammar declares", () => {
    const [entry] = manifest.contributes.grammars;
    assert.equal(entry.language, "osc2");
    assert.equal(entry.scopeName, "source.osc2");
    assert.equal(path.resolve(fromRoot(entry.path)), grammarFile);
    assert.equal(grammar.scopeName, entry.scopeName);
  });

  it("makes the server command and Python path machine settings (Remote or workspace in a remote window)", () => {
    const p = manifest.contributes.configuration.properties;
    for (const key of ["osc2.server.command", "osc2.server.pythonPath"]) {
      assert.equal(p[key].scope, "machine-overridable", key);
      assert.match(p[key].markdownDescription, /remote window/, key);
    }
  });

  it("shows “Run scenario” with an icon in the editor title", () => {
    const run = manifest.contributes.commands.find((c: { command: string }) => c.command === "osc2.runScenario");
    assert.equal(run.icon, "$(play)");
    const title = manifest.contributes.menus["editor/title/run"];
    assert.ok(title.some((m: { command: string; when: string }) => m.command === "osc2.runScenario" && m.when === "editorLangId == osc2"));
  });

  it("declares the settings with their defaults", () => {
    const p = manifest.contributes.configuration.properties;
    assert.deepEqual(p["osc2.server.command"].default, ["osc2lsp"]);
    assert.equal(p["osc2.server.command"].type, "array");
    assert.equal(p["osc2.server.pythonPath"].type, "string");
    assert.equal(p["osc2.strict"].default, false);
    assert.equal(p["osc2.inlayHints.enabled"].default, false);
    assert.deepEqual(p["osc2.trace.server"].enum, ["off", "messages", "verbose"]);
    assert.equal(p["osc2.trace.server"].default, "off");
  });

  it("contributes the three commands", () => {
    const titles = Object.fromEntries(
      manifest.contributes.commands.map((c: { command: string; category: string; title: string }) => [
        c.command,
        `${c.category}: ${c.title}`,
      ]),
    );
    assert.deepEqual(titles, {
      "osc2.runScenario": "OSC2: Run scenario",
      "osc2.showWitness": "OSC2: Show witness",
      "osc2.restartServer": "OSC2: Restart server",
    });
  });

  it("keeps sources, tests and node_modules out of the package", () => {
    const ignored = fs.readFileSync(fromRoot(".vscodeignore"), "utf8").split(/\r?\n/);
    for (const entry of ["src/**", "test/**", "node_modules/**", "scripts/**", "out/**"]) {
      assert.ok(ignored.includes(entry), `.vscodeignore lacks ${entry}`);
    }
  });
});

describe("TextMate grammar", () => {
  it("is the output of scripts/grammar.mjs", () => {
    const check = spawnSync(process.execPath, [fromRoot("scripts", "grammar.mjs"), "--check"], { encoding: "utf8" });
    assert.equal(check.status, 0, check.stderr);
  });

  it("has every scope it can produce asserted in test/grammar/*.test.osc", () => {
    const produced = new Set<string>();
    const visit = (node: unknown, regex?: string) => {
      if (Array.isArray(node)) return node.forEach((n) => visit(n, regex));
      if (node === null || typeof node !== "object") return;
      const rule = node as Record<string, unknown>;
      const source = (rule.match ?? rule.begin ?? regex) as string | undefined;
      for (const key of ["name", "contentName"]) {
        const name = rule[key];
        if (typeof name === "string") for (const n of expand(name, source)) for (const s of n.split(" ")) produced.add(s);
      }
      for (const value of Object.values(rule)) visit(value, source);
    };
    visit(grammar.patterns);
    visit(grammar.repository);

    const asserted = new Set<string>();
    const dir = fromRoot("test", "grammar");
    for (const file of fs.readdirSync(dir).filter((f) => f.endsWith(".test.osc"))) {
      for (const line of fs.readFileSync(path.join(dir, file), "utf8").split("\n")) {
        const m = /^#\s*(?:\^+|<[-~]+)\s+(.*)$/.exec(line);
        if (!m) continue;
        const positive = m[1].split(" - ")[0];
        for (const s of positive.trim().split(/\s+/)) if (s && s !== "-") asserted.add(s);
      }
    }
    const missing = [...produced].filter((s) => !asserted.has(s)).sort();
    assert.deepEqual(missing, [], `scopes without a grammar assertion: ${missing.join(", ")}`);
    assert.ok(produced.size > 80, `only ${produced.size} scopes found`);
  });
});

/** Expand `$1` in a scope name with the alternatives of the rule's first group, e.g. (enum|extend). */
function expand(name: string, regex: string | undefined): string[] {
  if (!name.includes("$1")) return [name];
  const group = regex ? /\(((?:\w+\|)+\w+)\)/.exec(regex) : null;
  assert.ok(group, `cannot expand ${name}`);
  return group[1].split("|").map((alternative) => name.replace("$1", alternative.toLowerCase()));
}

describe("language configuration", () => {
  const indentAfter = new RegExp(languageConfiguration.onEnterRules[0].beforeText);
  const increase = new RegExp(languageConfiguration.indentationRules.increaseIndentPattern);

  it("uses # comments, () and [] brackets, and off-side folding", () => {
    assert.equal(languageConfiguration.comments.lineComment, "#");
    assert.deepEqual(languageConfiguration.brackets, [["(", ")"], ["[", "]"]]);
    assert.equal(languageConfiguration.folding.offSide, true);
    const pairs = languageConfiguration.autoClosingPairs.map((p: { open: string }) => p.open);
    assert.deepEqual(pairs, ["(", "[", '"', "'"]);
  });

  it("indents after a line that ends with a colon", () => {
    for (const line of ["scenario cut_in:", "    do serial:", "  hero: vehicle with:", "    on @start:  # note", "do main: serial:"]) {
      assert.ok(indentAfter.test(line), line);
      assert.ok(increase.test(line), line);
    }
    for (const line of ["    x: speed", "# heading:", "    keep(x == 1)  # why:", "    wait @e", ""]) {
      assert.ok(!indentAfter.test(line), line);
      assert.ok(!increase.test(line), line);
    }
  });

  it("treats physical literals and |quoted| names as words", () => {
    const word = new RegExp(languageConfiguration.wordPattern.pattern, `g${languageConfiguration.wordPattern.flags}`);
    assert.deepEqual("x = 10kph + 1.5e3m - 15|foot/s| + straße".match(word), [
      "x",
      "10kph",
      "1.5e3m",
      "15|foot/s|",
      "straße",
    ]);
  });
});
