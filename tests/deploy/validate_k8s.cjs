// Validates Kubernetes objects against the API schemas bundled offline by the npm package
// kubernetes-models (Kubernetes 1.27 OpenAPI, ajv) and @kubernetes-models/prometheus-operator.
// stdin: a JSON array of objects (tests/deploy/kubernetes_test.py converts the YAML);
// stdout: one line per object; exit 1 when any object is invalid or of an unknown kind.
"use strict";
const path = require("path");
const docs = JSON.parse(require("fs").readFileSync(0, "utf8"));
let bad = 0;
for (const doc of docs) {
  const [group, version] = doc.apiVersion.includes("/") ? doc.apiVersion.split("/") : [null, doc.apiVersion];
  const pkg = group === "monitoring.coreos.com" ? "@kubernetes-models/prometheus-operator" : "kubernetes-models";
  const mod = path.posix.join(pkg, ...(group ? [group, version] : [version]), doc.kind);
  const name = `${doc.kind}/${doc.metadata && doc.metadata.name}`;
  let Model;
  try {
    const m = require(mod);
    Model = m[doc.kind] || m.default;
  } catch (e) {
    console.log(`INVALID ${name}: no schema for ${doc.apiVersion} ${doc.kind} (${mod})`);
    bad++;
    continue;
  }
  try {
    new Model(doc).validate();
    console.log(`valid ${name} (${doc.apiVersion})`);
  } catch (e) {
    console.log(`INVALID ${name}: ${e.message}`);
    bad++;
  }
}
process.exit(bad ? 1 : 0);
