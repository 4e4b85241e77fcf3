// Starts `spl lsp` for .tsm, .fm, .rm, .uvl and FeatureIDE .xml files; everything the
// editor shows (errors, definitions, completion, hover, outline, formatting) comes from it.
const vscode = require("vscode");
const { LanguageClient } = require("vscode-languageclient/node");

let client;

function activate(context) {
  const [command, ...args] = vscode.workspace.getConfiguration("spl").get("command");
  client = new LanguageClient(
    "spl",
    "spl",
    { command, args },
    {
      documentSelector: [
        { scheme: "file", language: "spl-tsm" },
        { scheme: "file", language: "spl-fm" },
        { scheme: "file", language: "spl-rm" },
        { scheme: "file", language: "uvl" },
        { scheme: "file", language: "xml" }, // the server checks FeatureIDE models only
      ],
    }
  );
  context.subscriptions.push(client);
  return client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
