import assert = require("node:assert/strict");
import * as path from "path";
import { describe, it } from "node:test";
import {
  checkerFailedMessage,
  interpretChecker,
  shellCommandLine,
  shellKind,
  toolCommand,
  witnessArgs,
} from "../../src/tools";

describe("toolCommand", () => {
  it("uses the bare name without a python path", () => {
    assert.equal(toolCommand("osc2run", undefined, "linux", () => true), "osc2run");
    assert.equal(toolCommand("osc2run", "", "linux", () => true), "osc2run");
  });

  it("prefers the script next to the interpreter", () => {
    assert.equal(toolCommand("osc2check", "/venv/bin/python", "linux", () => true), path.join("/venv/bin", "osc2check"));
    assert.equal(toolCommand("osc2check", "/venv/bin/python", "linux", () => false), "osc2check");
  });

  it("looks for .exe and Scripts\\ on Windows", () => {
    const seen: string[] = [];
    toolCommand("osc2run", "C:/env/python.exe", "win32", (f) => (seen.push(f), false));
    assert.deepEqual(seen, [path.join("C:/env", "osc2run.exe"), path.join("C:/env", "Scripts", "osc2run.exe")]);
  });
});

describe("shellCommandLine", () => {
  it("detects the shell", () => {
    assert.equal(shellKind("/bin/zsh", "darwin"), "posix");
    assert.equal(shellKind("C:\\Windows\\System32\\cmd.exe", "win32"), "cmd");
    assert.equal(shellKind("C:\\Program Files\\PowerShell\\7\\pwsh.exe", "win32"), "powershell");
    assert.equal(shellKind(undefined, "win32"), "powershell");
    assert.equal(shellKind(undefined, "linux"), "posix");
  });

  it("quotes for POSIX shells", () => {
    assert.equal(shellCommandLine(["osc2run", "/a/b.osc"], "/bin/bash"), "osc2run /a/b.osc");
    assert.equal(shellCommandLine(["osc2run", "/a b/it's.osc"], "/bin/bash"), `osc2run '/a b/it'\\''s.osc'`);
    assert.equal(shellCommandLine(["osc2run", "/x/$HOME`.osc"], "/usr/bin/fish"), "osc2run '/x/$HOME`.osc'");
  });

  it("quotes for PowerShell, with the call operator for a quoted program", () => {
    assert.equal(shellCommandLine(["osc2run", "C:\\s\\a.osc"], "pwsh.exe"), "osc2run C:\\s\\a.osc");
    assert.equal(
      shellCommandLine(["C:\\My Env\\Scripts\\osc2run.exe", "C:\\it's here\\a.osc"], "powershell.exe"),
      "& 'C:\\My Env\\Scripts\\osc2run.exe' 'C:\\it''s here\\a.osc'",
    );
  });

  it("quotes for cmd.exe", () => {
    assert.equal(shellCommandLine(["osc2run", "C:\\a b\\c.osc"], "cmd.exe"), `osc2run "C:\\a b\\c.osc"`);
  });
});

describe("interpretChecker", () => {
  it("passes the arguments of the witness command", () => {
    assert.deepEqual(witnessArgs("/a.osc"), ["--witness", "/a.osc", "--output-format", "json"]);
  });

  it("shows JSON the checker printed, pretty-printed", () => {
    const outcome = interpretChecker({ exitCode: 0, stdout: '{"a":1}', stderr: "" });
    assert.deepEqual(outcome, { kind: "json", text: '{\n  "a": 1\n}\n', exitCode: 0 });
  });

  it("keeps the exit code when JSON comes with findings", () => {
    const outcome = interpretChecker({ exitCode: 1, stdout: "[]", stderr: "1 error" });
    assert.equal(outcome.kind, "json");
    assert.equal(outcome.kind === "json" && outcome.exitCode, 1);
  });

  it("reports the checker's last error line when --witness is unknown", () => {
    const outcome = interpretChecker({
      exitCode: 2,
      stdout: "",
      stderr: "usage: osc2check [-h] paths\nosc2check: error: unrecognized arguments: --witness\n",
    });
    assert.deepEqual(outcome, {
      kind: "failed",
      summary: "osc2check: error: unrecognized arguments: --witness",
      exitCode: 2,
    });
    assert.equal(
      checkerFailedMessage(outcome as { summary: string; exitCode: number }),
      "OSC2: osc2check --witness failed (exit code 2): osc2check: error: unrecognized arguments: --witness",
    );
  });

  it("never shows output that is not JSON as a witness", () => {
    const outcome = interpretChecker({ exitCode: 0, stdout: "a.osc:1:1: S001 parse error", stderr: "" });
    assert.deepEqual(outcome, { kind: "failed", summary: "a.osc:1:1: S001 parse error", exitCode: 0 });
  });

  it("recognises a missing program", () => {
    assert.deepEqual(
      interpretChecker({ exitCode: null, stdout: "", stderr: "", spawnError: { code: "ENOENT", message: "spawn osc2check ENOENT" } }),
      { kind: "not-found" },
    );
  });

  it("reports a time-out without partial output", () => {
    const outcome = interpretChecker({ exitCode: null, stdout: '{"partial":', stderr: "", spawnError: { message: "stopped after the time limit of 300 s" } });
    assert.deepEqual(outcome, { kind: "failed", summary: "stopped after the time limit of 300 s", exitCode: null });
  });
});
