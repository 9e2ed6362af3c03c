// thermnet for VS Code: highlighting and snippets are declarative (package.json);
// this script only starts the language server `thermnet lsp` (stdio), and only when
// a `thermnet` executable is on PATH and vscode-languageclient is installed.
'use strict';

const fs = require('fs');
const path = require('path');
const vscode = require('vscode');

let client;

/** Full path of an executable found in an absolute PATH entry, or undefined. */
function findOnPath(name) {
  // Relative entries ('.', 'bin') would find a `thermnet` planted in an untrusted workspace.
  const dirs = (process.env.PATH || '').split(path.delimiter).filter((d) => d && path.isAbsolute(d));
  const exts = process.platform === 'win32'
    ? (process.env.PATHEXT || '.EXE;.CMD;.BAT;.COM').split(';').concat([''])
    : [''];
  for (const dir of dirs) {
    for (const ext of exts) {
      const candidate = path.join(dir, name + ext);
      try {
        const st = fs.statSync(candidate);
        if (!st.isFile()) continue;
        if (process.platform !== 'win32') fs.accessSync(candidate, fs.constants.X_OK);
        return candidate;
      } catch (_) {
        // not here
      }
    }
  }
  return undefined;
}

function activate(context) {
  const log = vscode.window.createOutputChannel('thermnet');
  context.subscriptions.push(log);

  const exe = findOnPath('thermnet');
  if (!exe) {
    log.appendLine('thermnet was not found on PATH: highlighting and snippets only, no language server.');
    return;
  }

  let lc;
  try {
    lc = require('vscode-languageclient/node');
  } catch (err) {
    log.appendLine(`vscode-languageclient is not installed (run "npm install" in the extension folder): ${err.message}`);
    return;
  }

  const serverOptions = {
    run: { command: exe, args: ['lsp'], transport: lc.TransportKind.stdio },
    debug: { command: exe, args: ['lsp'], transport: lc.TransportKind.stdio },
  };
  const clientOptions = {
    documentSelector: [
      { scheme: 'file', language: 'tnet' },
      { scheme: 'untitled', language: 'tnet' },
    ],
    outputChannel: log,
  };
  client = new lc.LanguageClient('thermnet', 'thermnet language server', serverOptions, clientOptions);
  log.appendLine(`starting ${exe} lsp`);
  client.start().catch((err) => {
    log.appendLine(`the thermnet language server failed to start: ${err && err.message ? err.message : err}`);
  });
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
