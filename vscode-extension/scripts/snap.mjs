// Grammar snapshot tests with vscode-tmgrammar-snap.
//
//   node scripts/snap.mjs            compare against the stored snapshots
//   node scripts/snap.mjs --update   rewrite the stored snapshots
//
// 1. test/grammar/all_constructs.osc (our own file) against
//    test/grammar/all_constructs.osc.snap, the usual way.
// 2. The design paper's two scenarios, read from the shared conformance folder
//    (../../shared/conformance/seed relative to this package, or $OSC2_SEED_DIR).
//    Those files must not be copied into this repository, and a .snap file
//    would contain their text line by line. So the repository keeps only the
//    scope lines (test/grammar/seed/<name>.scopes, source text stripped); at
//    test time the .osc is copied into a temporary folder, the .snap is rebuilt
//    from the stored scopes and the current source, and vscode-tmgrammar-snap
//    compares as usual. When the folder is absent those snapshots are skipped.

import { spawnSync } from "node:child_process";
import { copyFileSync, existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { basename, dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";

const root = resolve(dirname(fileURLToPath(import.meta.url)), "..");
const update = process.argv.includes("--update");
const snapBin = join(root, "node_modules", ".bin", process.platform === "win32" ? "vscode-tmgrammar-snap.cmd" : "vscode-tmgrammar-snap");
const grammar = join(root, "syntaxes", "osc2.tmLanguage.json");
const config = join(root, "package.json");

const OWN = [join(root, "test", "grammar", "all_constructs.osc")];
const SEED_NAMES = ["cut_in_and_stop.osc", "braking_friction.osc"];
const seedDir = process.env.OSC2_SEED_DIR
  ? resolve(process.env.OSC2_SEED_DIR)
  : resolve(root, "..", "..", "shared", "conformance", "seed");
const scopesDir = join(root, "test", "grammar", "seed");

const HEADER = (name) =>
  `## Scopes of shared/conformance/seed/${name} (vscode-tmgrammar-snap format, source text stripped).\n` +
  `## Rebuilt into a .snap at test time by scripts/snap.mjs; regenerate with \`npm run snap:update\`.\n`;

let failures = 0;
const results = [];

function runSnap(files) {
  const args = ["--config", config, "-g", grammar, ...(update ? ["-u"] : []), ...files];
  const proc = spawnSync(snapBin, args, { encoding: "utf8", shell: process.platform === "win32" });
  const out = (proc.stdout + proc.stderr)
    .split("\n")
    .filter((l) => !/Unknown user config|npm warn/.test(l))
    .join("\n")
    .trim();
  if (out) console.log(out);
  return proc.status === 0;
}

function record(name, ok, note = "") {
  results.push(`${ok ? "ok  " : "FAIL"}  ${name}${note ? "  " + note : ""}`);
  if (!ok) failures++;
}

// ---- 1. our own construct file
for (const file of OWN) {
  const name = `test/grammar/${basename(file)}`;
  if (!update && !existsSync(file + ".snap")) {
    console.error(`${name}.snap is missing: run \`npm run snap:update\` and commit it`);
    record(name, false, "(snapshot missing)");
    continue;
  }
  record(name, runSnap([file]));
}

// ---- 2. the design paper's scenarios, when the shared folder is present
if (!existsSync(seedDir)) {
  results.push(`skip  seed snapshots: ${seedDir} not found`);
} else {
  const work = mkdtempSync(join(tmpdir(), "osc2-seed-snap-"));
  try {
    for (const name of SEED_NAMES) {
      const label = `seed/${name}`;
      const source = join(seedDir, name);
      const stored = join(scopesDir, name.replace(/\.osc$/, ".scopes"));
      if (!existsSync(source)) {
        console.error(`${source} not found`);
        record(label, false, "(seed file missing)");
        continue;
      }
      const copy = join(work, name);
      copyFileSync(source, copy);
      if (!update) {
        if (!existsSync(stored)) {
          console.error(`${stored} is missing: run \`npm run snap:update\` and commit it`);
          record(label, false, "(stored scopes missing)");
          continue;
        }
        const rebuilt = rebuildSnap(readFileSync(stored, "utf8"), readFileSync(copy, "utf8"));
        if (rebuilt === null) {
          console.error(`${label}: the seed file's line count no longer matches ${stored}; review and run \`npm run snap:update\``);
          record(label, false, "(seed file changed)");
          continue;
        }
        writeFileSync(copy + ".snap", rebuilt);
      }
      const ok = runSnap([copy]);
      if (update && ok) writeFileSync(stored, HEADER(name) + stripSnap(readFileSync(copy + ".snap", "utf8")));
      record(label, ok);
    }
  } finally {
    rmSync(work, { recursive: true, force: true });
  }
}

/** Remove the source text from a .snap: every ">line" becomes ">". */
function stripSnap(snap) {
  return snap
    .split("\n")
    .map((l) => (l.startsWith(">") ? ">" : l))
    .join("\n");
}

/** Put the current source lines back into stripped scopes; null if they no longer fit. */
function rebuildSnap(stored, source) {
  const body = stored.split("\n").filter((l) => !l.startsWith("##"));
  const lines = source.split(/\r\n|\n/);
  const markers = body.filter((l) => l.startsWith(">")).length;
  if (markers !== lines.length) return null;
  let i = 0;
  return body.map((l) => (l.startsWith(">") ? ">" + lines[i++] : l)).join("\n");
}

console.log("\nsnapshot results:");
for (const line of results) console.log("  " + line);
process.exit(failures === 0 ? 0 : 1);
