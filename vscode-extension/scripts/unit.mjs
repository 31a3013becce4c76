// Unit tests: compile test/unit/**/*.ts with esbuild into out/unit and run
// them with node's built-in test runner. The client tests load the bundled
// dist/extension.js, so it is rebuilt first.

import * as esbuild from "esbuild";
import { spawnSync } from "node:child_process";
import { readdirSync, rmSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const root = join(dirname(fileURLToPath(import.meta.url)), "..");
const outdir = join(root, "out", "unit");

const bundle = spawnSync(process.execPath, [join(root, "scripts", "bundle.mjs")], { stdio: "inherit" });
if (bundle.status !== 0) process.exit(bundle.status ?? 1);

rmSync(outdir, { recursive: true, force: true });
const tests = readdirSync(join(root, "test", "unit")).filter((f) => f.endsWith(".test.ts"));
await esbuild.build({
  entryPoints: [
    ...tests.map((f) => join(root, "test", "unit", f)),
    join(root, "test", "unit", "helpers", "fakeServer.ts"),
  ],
  outdir,
  outbase: join(root, "test", "unit"),
  outExtension: { ".js": ".cjs" },
  bundle: true,
  platform: "node",
  format: "cjs",
  target: "node18",
  external: ["vscode"],
  sourcemap: "inline",
  logLevel: "warning",
});

const files = tests.map((f) => join(outdir, f.replace(/\.ts$/, ".cjs")));
const run = spawnSync(process.execPath, ["--test", "--test-reporter=spec", ...files], {
  stdio: "inherit",
  cwd: root,
});
process.exit(run.status ?? 1);
