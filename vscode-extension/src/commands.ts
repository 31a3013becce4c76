// "OSC2: Run scenario" and "OSC2: Show witness".

import * as cp from "child_process";
import * as fs from "fs";
import * as path from "path";
import * as vscode from "vscode";
import { OPEN_SETTINGS, SHOW_OUTPUT, openServerSettings, readServerSettings } from "./server";
import {
  ProcessResult,
  checkerFailedMessage,
  checkerNotFoundMessage,
  interpretChecker,
  shellCommandLine,
  toolCommand,
  witnessArgs,
} from "./tools";

export const RUN_TERMINAL_NAME = "OSC2: run";
const CHECKER_TIMEOUT_MS = 5 * 60 * 1000;

function pythonPath(): string {
  return readServerSettings().settings.pythonPath;
}

/** The saved .osc file of the active editor, or undefined after telling the user why not. */
async function activeScenarioFile(): Promise<vscode.TextDocument | undefined> {
  const document = vscode.window.activeTextEditor?.document;
  if (!document || document.languageId !== "osc2") {
    void vscode.window.showErrorMessage("OSC2: open an OSC2 (.osc) file first.");
    return undefined;
  }
  if (document.isUntitled) {
    void vscode.window.showErrorMessage("OSC2: save the scenario to a .osc file first.");
    return undefined;
  }
  if (document.isDirty && !(await document.save())) {
    void vscode.window.showErrorMessage("OSC2: the file could not be saved.");
    return undefined;
  }
  return document;
}

function workingDirectory(document: vscode.TextDocument): string | undefined {
  const dir = vscode.workspace.getWorkspaceFolder(document.uri)?.uri.fsPath ?? path.dirname(document.uri.fsPath);
  return fs.existsSync(dir) ? dir : undefined;
}

/** Open (or reuse) a terminal and run `osc2run <file>` in it. */
export async function runScenario(): Promise<void> {
  const document = await activeScenarioFile();
  if (!document) return;
  const command = toolCommand("osc2run", pythonPath());
  const reusable = vscode.window.terminals.find((t) => t.name === RUN_TERMINAL_NAME && t.exitStatus === undefined);
  const terminal =
    reusable ?? vscode.window.createTerminal({ name: RUN_TERMINAL_NAME, cwd: workingDirectory(document) });
  terminal.show();
  terminal.sendText(shellCommandLine([command, document.uri.fsPath], vscode.env.shell));
}

function runProcess(command: string, args: string[], cwd: string | undefined): Promise<ProcessResult> {
  return new Promise((resolve) => {
    cp.execFile(
      command,
      args,
      { cwd, timeout: CHECKER_TIMEOUT_MS, maxBuffer: 64 * 1024 * 1024, windowsHide: true },
      (error, stdout, stderr) => {
        let exitCode: number | null = 0;
        let spawnError: ProcessResult["spawnError"];
        if (error) {
          exitCode = typeof error.code === "number" ? error.code : null;
          if (typeof error.code === "string") {
            spawnError = { code: error.code, message: error.message };
          } else if (error.killed) {
            spawnError = { message: `stopped after the time limit of ${CHECKER_TIMEOUT_MS / 1000} s` };
          } else if (error.signal) {
            spawnError = { message: `terminated by ${error.signal}` };
          }
        }
        resolve({ exitCode, stdout: String(stdout), stderr: String(stderr), spawnError });
      },
    );
  });
}

/** Run `osc2check --witness <file> --output-format json` and show its JSON in a new editor. */
export async function showWitness(output: vscode.OutputChannel): Promise<void> {
  const document = await activeScenarioFile();
  if (!document) return;
  const command = toolCommand("osc2check", pythonPath());
  const args = witnessArgs(document.uri.fsPath);
  const cwd = workingDirectory(document);
  output.appendLine(`[osc2check] $ ${[command, ...args].join(" ")}${cwd ? `   (in ${cwd})` : ""}`);

  const result = await vscode.window.withProgress(
    { location: vscode.ProgressLocation.Notification, title: "OSC2: computing the witness…" },
    () => runProcess(command, args, cwd),
  );
  output.appendLine(`[osc2check] exit code ${result.exitCode ?? "none"}${result.spawnError ? ` (${result.spawnError.message})` : ""}`);
  if (result.stderr.trim() !== "") output.appendLine(`[osc2check] stderr:\n${result.stderr.trimEnd()}`);

  const outcome = interpretChecker(result);
  switch (outcome.kind) {
    case "json": {
      const shown = await vscode.workspace.openTextDocument({ language: "json", content: outcome.text });
      await vscode.window.showTextDocument(shown, { preview: false });
      if (outcome.exitCode !== 0) {
        void vscode.window.showWarningMessage(
          `OSC2: osc2check exited with code ${outcome.exitCode ?? "none"}; the JSON shown is what it printed.`,
        );
      }
      return;
    }
    case "not-found": {
      const message = checkerNotFoundMessage(command);
      output.appendLine(`[osc2check] ${message}`);
      const choice = await vscode.window.showErrorMessage(message, OPEN_SETTINGS);
      if (choice === OPEN_SETTINGS) await openServerSettings();
      return;
    }
    case "failed": {
      if (result.stdout.trim() !== "") output.appendLine(`[osc2check] stdout:\n${result.stdout.trimEnd()}`);
      const choice = await vscode.window.showErrorMessage(checkerFailedMessage(outcome), SHOW_OUTPUT);
      if (choice === SHOW_OUTPUT) output.show(true);
      return;
    }
  }
}
