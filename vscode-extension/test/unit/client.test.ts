// The bundled extension (dist/extension.js, with the real vscode-languageclient
// inside) activated against a stand-in `vscode` module and a fake language
// server over stdio. No VS Code is needed.

import assert = require("node:assert/strict");
import * as fs from "fs";
import { createRequire } from "module";
import * as os from "os";
import * as path from "path";
import { after, afterEach, before, beforeEach, describe, it } from "node:test";
import { VscodeMock, fakeDocument, installVscodeMock } from "./helpers/vscodeMock";
import { fromRoot, waitFor } from "./helpers/paths";

const posix = process.platform !== "win32";
const mock = new VscodeMock();
installVscodeMock(mock);

interface ExtensionModule {
  activate(context: { subscriptions: { dispose(): unknown }[] }): Promise<void>;
  deactivate(): Promise<void>;
}
const extension = createRequire(__filename)(fromRoot("dist", "extension.js")) as ExtensionModule;
const fakeServer = path.join(__dirname, "helpers", "fakeServer.cjs");

let tmp: string;
let log: string;
let context: { subscriptions: { dispose(): unknown }[] };
const originalPath = process.env.PATH;

function received(): { method?: string; params?: any }[] {
  if (!fs.existsSync(log)) return [];
  return fs
    .readFileSync(log, "utf8")
    .split("\n")
    .filter((l) => l !== "")
    .map((l) => JSON.parse(l));
}

function script(name: string, body: string): string {
  const file = path.join(tmp, name);
  fs.mkdirSync(path.dirname(file), { recursive: true });
  fs.writeFileSync(file, `#!/bin/sh\n${body}\n`, { mode: 0o755 });
  return file;
}

async function activate(settings: Record<string, unknown>): Promise<void> {
  mock.settings = { ...settings };
  await extension.activate(context);
}

before(() => {
  tmp = fs.mkdtempSync(path.join(os.tmpdir(), "osc2-client-test-"));
});

after(() => {
  fs.rmSync(tmp, { recursive: true, force: true });
});

beforeEach(() => {
  mock.reset();
  log = path.join(tmp, `lsp-${Date.now()}-${Math.random().toString(16).slice(2)}.log`);
  process.env.FAKE_LSP_LOG = log;
  context = { subscriptions: [] };
});

afterEach(async () => {
  await extension.deactivate();
  for (const d of context.subscriptions) d.dispose();
  process.env.PATH = originalPath;
});

describe("language client", () => {
  it("registers exactly the commands that package.json contributes", async () => {
    await activate({ "osc2.server.command": [process.execPath, fakeServer] });
    const manifest = JSON.parse(fs.readFileSync(fromRoot("package.json"), "utf8"));
    const contributed = manifest.contributes.commands.map((c: { command: string }) => c.command).sort();
    assert.deepEqual([...mock.commands.keys()].sort(), contributed);
  });

  it("starts the configured command over stdio and sends the options as initializationOptions", async () => {
    await activate({ "osc2.server.command": [process.execPath, fakeServer], "osc2.strict": true });
    const initialize = received().find((m) => m.method === "initialize");
    assert.ok(initialize, "the server got no initialize request");
    assert.deepEqual(initialize.params.initializationOptions, { strict: true, inlayHints: { enabled: false } });
    await waitFor("initialized", () => received().some((m) => m.method === "initialized"));
    assert.deepEqual(mock.messages, []);
    assert.ok(mock.output.some((l) => l.includes("language server running")));
  });

  it("sends strict: null while osc2.strict is not set, so the project's configuration decides", async () => {
    await activate({ "osc2.server.command": [process.execPath, fakeServer], "osc2.inlayHints.enabled": true });
    const initialize = received().find((m) => m.method === "initialize");
    assert.deepEqual(initialize?.params.initializationOptions, { strict: null, inlayHints: { enabled: true } });
    await waitFor("the answer to workspace/configuration", () => received().some((m: any) => m.id === "pull-osc2"));
    const [section] = (received().find((m: any) => m.id === "pull-osc2") as any).result;
    assert.equal(section.strict, null);
    assert.deepEqual(section.inlayHints, { enabled: true });
    assert.deepEqual(section.server.command, [process.execPath, fakeServer]);
  });

  it("answers workspace/configuration with an explicit osc2.strict", async () => {
    await activate({ "osc2.server.command": [process.execPath, fakeServer], "osc2.strict": false });
    await waitFor("the answer to workspace/configuration", () => received().some((m: any) => m.id === "pull-osc2"));
    const [section] = (received().find((m: any) => m.id === "pull-osc2") as any).result;
    assert.equal(section.strict, false);
    assert.deepEqual(section.inlayHints, { enabled: false });
  });

  it("sends workspace/didChangeConfiguration when osc2.strict or osc2.inlayHints change", async () => {
    await activate({ "osc2.server.command": [process.execPath, fakeServer] });
    mock.changeSettings({ "osc2.inlayHints.enabled": true });
    await waitFor("didChangeConfiguration", () => received().some((m) => m.method === "workspace/didChangeConfiguration"));
    const change = received().find((m) => m.method === "workspace/didChangeConfiguration");
    assert.deepEqual(change?.params, { settings: { osc2: { strict: null, inlayHints: { enabled: true } } } });
    mock.changeSettings({ "osc2.strict": true });
    await waitFor("second didChangeConfiguration", () =>
      received().filter((m) => m.method === "workspace/didChangeConfiguration").length === 2,
    );
    const last = received().filter((m) => m.method === "workspace/didChangeConfiguration")[1];
    assert.deepEqual(last.params, { settings: { osc2: { strict: true, inlayHints: { enabled: true } } } });
    assert.equal(received().filter((m) => m.method === "initialize").length, 1, "options changes must not restart");
  });

  it("restarts the server when an osc2.server setting changes", async () => {
    await activate({ "osc2.server.command": [process.execPath, fakeServer] });
    mock.changeSettings({ "osc2.server.command": [process.execPath, fakeServer, "--second"] });
    await waitFor("a second initialize", () => received().filter((m) => m.method === "initialize").length === 2);
    const methods = received().map((m) => m.method);
    assert.ok(methods.indexOf("shutdown") < methods.lastIndexOf("initialize"), "old server shut down first");
  });

  it("restarts the server on “OSC2: Restart server”", async () => {
    await activate({ "osc2.server.command": [process.execPath, fakeServer] });
    await mock.commands.get("osc2.restartServer")!();
    assert.equal(received().filter((m) => m.method === "initialize").length, 2);
    assert.equal(received().filter((m) => m.method === "shutdown").length, 1);
  });

  it("explains how to fix a missing server command and offers the settings", async () => {
    mock.answers = [{ pattern: /was not found/, item: "Open Settings" }];
    await activate({ "osc2.server.command": ["osc2lsp-that-does-not-exist"] });
    assert.equal(mock.messages.length, 1);
    const [message] = mock.messages;
    assert.equal(message.severity, "error");
    assert.match(message.text, /`osc2lsp-that-does-not-exist` was not found/);
    assert.match(message.text, /pip install osc2-toolkit/);
    assert.match(message.text, /osc2\.server\.pythonPath/);
    assert.deepEqual(message.items, ["Open Settings", "Show Output"]);
    await waitFor("open settings", () => mock.executed.some((e) => e.command === "workbench.action.openSettings"));
    assert.deepEqual(mock.executed.find((e) => e.command === "workbench.action.openSettings")?.args, ["osc2.server"]);
  });

  it("in a remote window, says where machine settings are read and opens the Remote settings", async () => {
    mock.remoteName = "ssh-remote";
    mock.answers = [{ pattern: /was not found/, item: "Open Settings" }];
    await activate({ "osc2.server.command": ["osc2lsp-that-does-not-exist"] });
    assert.equal(mock.messages.length, 1);
    assert.match(mock.messages[0].text, /remote window \(ssh-remote\)/);
    assert.match(mock.messages[0].text, /Remote settings or the workspace's settings/);
    await waitFor("open remote settings", () =>
      mock.executed.some((e) => e.command === "workbench.action.openRemoteSettings"),
    );
    const opened = mock.executed.find((e) => e.command === "workbench.action.openRemoteSettings");
    assert.deepEqual(opened?.args, [{ query: "osc2.server" }]);
    assert.ok(mock.output.some((l) => l.includes("osc2.server.command") && l.includes("Remote settings (ssh-remote)")));
  });

  it("logs which settings the server command came from", async () => {
    await activate({ "osc2.server.command": [process.execPath, fakeServer] });
    assert.ok(mock.output.some((l) => l.startsWith("[osc2] osc2.server.command") && l.endsWith("from User settings")));
    assert.ok(mock.output.some((l) => l.startsWith("[osc2] osc2.server.pythonPath") && l.endsWith("from the default")));
  });

  it("lets a stopped server exit by itself instead of killing it", async () => {
    await activate({ "osc2.server.command": [process.execPath, fakeServer] });
    await extension.deactivate();
    assert.ok(mock.output.some((l) => l.includes("the server exited (code 0)")), mock.output.join("\n"));
    assert.ok(!mock.output.some((l) => l.includes("did not exit")));
  });

  it("reports a python path that does not exist", async () => {
    await activate({ "osc2.server.pythonPath": path.join(tmp, "no", "python3") });
    assert.equal(mock.messages.length, 1);
    assert.match(mock.messages[0].text, /Python interpreter .* was not found/);
    assert.match(mock.messages[0].text, /pip install osc2-toolkit/);
  });

  it("runs `<python> -m osc2lsp` and reports once when the module is missing", { skip: !posix }, async () => {
    const argvFile = path.join(tmp, "python-argv.txt");
    const python = script(
      "venv/bin/python3",
      `printf '%s\\n' "$@" > '${argvFile}'\necho "python3: No module named osc2lsp" >&2\nexit 1`,
    );
    await activate({ "osc2.server.pythonPath": python, "osc2.server.command": ["ignored"] });
    await waitFor("the error message", () => mock.messages.length > 0);
    await new Promise((resolve) => setTimeout(resolve, 300)); // a duplicate would arrive now
    assert.deepEqual(fs.readFileSync(argvFile, "utf8").trim().split("\n"), ["-m", "osc2lsp"]);
    assert.equal(mock.messages.length, 1, JSON.stringify(mock.messages));
    assert.match(mock.messages[0].text, /exited during start-up/);
    assert.match(mock.messages[0].text, /-m pip install osc2-toolkit/);
    assert.ok(mock.output.join("\n").includes("No module named osc2lsp"), "server stderr goes to the output channel");
  });
});

describe("OSC2: Run scenario", () => {
  it("opens a terminal running osc2run on the current file", async () => {
    await activate({ "osc2.server.command": [process.execPath, fakeServer] });
    mock.activeDocument = fakeDocument("/work/scenarios/cut in.osc");
    mock.shell = "/bin/bash";
    await mock.commands.get("osc2.runScenario")!();
    assert.equal(mock.terminals.length, 1);
    assert.equal(mock.terminals[0].name, "OSC2: run");
    assert.ok(mock.terminals[0].shown);
    assert.deepEqual(mock.terminals[0].sent, ["osc2run '/work/scenarios/cut in.osc'"]);
    await mock.commands.get("osc2.runScenario")!();
    assert.equal(mock.terminals.length, 1, "the terminal is reused");
  });

  it("prefers the osc2run installed next to osc2.server.pythonPath", { skip: !posix }, async () => {
    const python = script("env1/bin/python", "exit 1");
    const osc2run = script("env1/bin/osc2run", "exit 0");
    await activate({ "osc2.server.command": [process.execPath, fakeServer] });
    mock.settings["osc2.server.pythonPath"] = python;
    mock.activeDocument = fakeDocument("/w/a.osc");
    await mock.commands.get("osc2.runScenario")!();
    assert.deepEqual(mock.terminals[0].sent, [`${osc2run} /w/a.osc`]);
  });

  it("refuses a file that is not OSC2", async () => {
    await activate({ "osc2.server.command": [process.execPath, fakeServer] });
    mock.activeDocument = fakeDocument("/w/notes.txt", "plaintext");
    await mock.commands.get("osc2.runScenario")!();
    assert.equal(mock.terminals.length, 0);
    assert.match(mock.messages[0].text, /open an OSC2 \(\.osc\) file first/);
  });
});

describe("OSC2: Show witness", { skip: !posix }, () => {
  function fakeChecker(body: string): string {
    const bin = path.join(tmp, `bin-${Math.random().toString(16).slice(2)}`);
    const argvFile = path.join(bin, "argv.txt");
    script(path.relative(tmp, path.join(bin, "osc2check")), `printf '%s\\n' "$@" > '${argvFile}'\n${body}`);
    process.env.PATH = `${bin}${path.delimiter}${originalPath}`;
    return argvFile;
  }

  it("shows the checker's JSON in a new untitled JSON document", async () => {
    const argvFile = fakeChecker(`printf '{"scenario": "cut_in", "witness": {"ego.speed": 13.9}}'`);
    await activate({ "osc2.server.command": [process.execPath, fakeServer] });
    mock.activeDocument = fakeDocument(path.join(tmp, "cut_in.osc"));
    await mock.commands.get("osc2.showWitness")!();
    assert.deepEqual(fs.readFileSync(argvFile, "utf8").trim().split("\n"), [
      "--witness",
      path.join(tmp, "cut_in.osc"),
      "--output-format",
      "json",
    ]);
    assert.equal(mock.openedDocuments.length, 1);
    assert.equal(mock.openedDocuments[0].language, "json");
    assert.deepEqual(JSON.parse(mock.openedDocuments[0].content ?? ""), {
      scenario: "cut_in",
      witness: { "ego.speed": 13.9 },
    });
    assert.deepEqual(mock.messages, []);
  });

  it("shows the checker's own error when --witness is not available", async () => {
    fakeChecker(
      `echo "usage: osc2check [-h] [--output-format {text,json}] paths" >&2\n` +
        `echo "osc2check: error: unrecognized arguments: --witness" >&2\nexit 2`,
    );
    mock.answers = [{ pattern: /failed/, item: "Show Output" }];
    await activate({ "osc2.server.command": [process.execPath, fakeServer] });
    mock.activeDocument = fakeDocument(path.join(tmp, "cut_in.osc"));
    await mock.commands.get("osc2.showWitness")!();
    assert.equal(mock.openedDocuments.length, 0, "nothing is shown in place of a witness");
    assert.equal(mock.messages.length, 1);
    assert.equal(
      mock.messages[0].text,
      "OSC2: osc2check --witness failed (exit code 2): osc2check: error: unrecognized arguments: --witness",
    );
    assert.ok(mock.output.some((l) => l.includes("usage: osc2check")), "full stderr in the output channel");
    assert.ok(mock.executed.some((e) => e.command === "<show output>"));
  });

  it("says how to install osc2check when it is missing", async () => {
    process.env.PATH = path.join(tmp, "empty-bin");
    await activate({ "osc2.server.command": [process.execPath, fakeServer] });
    mock.activeDocument = fakeDocument(path.join(tmp, "cut_in.osc"));
    await mock.commands.get("osc2.showWitness")!();
    assert.equal(mock.openedDocuments.length, 0);
    assert.match(mock.messages[0].text, /`osc2check` was not found/);
    assert.match(mock.messages[0].text, /pip install osc2-toolkit/);
  });
});
