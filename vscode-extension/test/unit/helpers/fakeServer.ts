// A minimal language server over stdio for the client tests. It answers
// initialize and shutdown, asks for the `osc2` settings after initialized, and
// appends every message it receives, one JSON per line, to the file named by
// FAKE_LSP_LOG.

import * as fs from "fs";

const log = process.env.FAKE_LSP_LOG;
let buffer = Buffer.alloc(0);

function send(message: object): void {
  const body = JSON.stringify(message);
  process.stdout.write(`Content-Length: ${Buffer.byteLength(body)}\r\n\r\n${body}`);
}

process.stdin.on("data", (chunk: Buffer) => {
  buffer = Buffer.concat([buffer, chunk]);
  for (;;) {
    const headerEnd = buffer.indexOf("\r\n\r\n");
    if (headerEnd < 0) return;
    const length = Number(/Content-Length: (\d+)/i.exec(buffer.subarray(0, headerEnd).toString())?.[1]);
    if (buffer.length < headerEnd + 4 + length) return;
    const message = JSON.parse(buffer.subarray(headerEnd + 4, headerEnd + 4 + length).toString());
    buffer = buffer.subarray(headerEnd + 4 + length);
    if (log) fs.appendFileSync(log, JSON.stringify(message) + "\n");
    if (message.method === "initialize") {
      send({ jsonrpc: "2.0", id: message.id, result: { capabilities: { textDocumentSync: 1 }, serverInfo: { name: "fake" } } });
    } else if (message.method === "initialized") {
      // like osc2lsp: ask for the `osc2` section (the answer is logged as it arrives)
      send({ jsonrpc: "2.0", id: "pull-osc2", method: "workspace/configuration", params: { items: [{ section: "osc2" }] } });
    } else if (message.method === "shutdown") {
      send({ jsonrpc: "2.0", id: message.id, result: null });
    } else if (message.method === "exit") {
      process.exit(0);
    }
  }
});
