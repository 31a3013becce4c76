// Entry point of the OSC2 extension: the osc2lsp client and three commands.

import * as vscode from "vscode";
import { runScenario, showWitness } from "./commands";
import { CLIENT_NAME, ServerController } from "./server";

const RESTART_DEBOUNCE_MS = 300;

let controller: ServerController | undefined;

export async function activate(context: vscode.ExtensionContext): Promise<void> {
  const output = vscode.window.createOutputChannel(CLIENT_NAME);
  const server = new ServerController(output);
  controller = server;
  context.subscriptions.push(output, server);

  context.subscriptions.push(
    vscode.commands.registerCommand("osc2.runScenario", () => runScenario()),
    vscode.commands.registerCommand("osc2.showWitness", () => showWitness(output)),
    vscode.commands.registerCommand("osc2.restartServer", async () => {
      output.appendLine("[osc2] restart requested");
      await server.restart();
      if (server.running) void vscode.window.setStatusBarMessage("OSC2 language server restarted", 3000);
    }),
  );

  let restartTimer: ReturnType<typeof setTimeout> | undefined;
  context.subscriptions.push(
    { dispose: () => restartTimer !== undefined && clearTimeout(restartTimer) },
    vscode.workspace.onDidChangeConfiguration((event) => {
      if (event.affectsConfiguration("osc2.server")) {
        if (restartTimer !== undefined) clearTimeout(restartTimer);
        restartTimer = setTimeout(() => {
          restartTimer = undefined;
          output.appendLine("[osc2] osc2.server settings changed: restarting the server");
          void server.restart();
        }, RESTART_DEBOUNCE_MS);
      } else if (event.affectsConfiguration("osc2.strict") || event.affectsConfiguration("osc2.inlayHints")) {
        void server.notifyOptions();
      }
    }),
  );

  await server.start();
}

export async function deactivate(): Promise<void> {
  const server = controller;
  controller = undefined;
  await server?.stop();
}
