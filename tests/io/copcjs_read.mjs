// copcjs_read.mjs NODE_MODULES FILE: reads a COPC file with copc.js (the npm package
// `copc`, decoding through laz-perf) and prints, as one JSON object, what
// `copc_tool dump FILE` prints from io::CopcReader: the info, the nodes with points and
// their counts, and over all points the count, the bounds and the sums of the coordinates
// in whole millimetres (as decimal strings) and the count of each role (ASPRS class 2 ground, 64 target, any
// other environment, as the LAS reader maps them). Every hierarchy page is loaded and
// every node's points decoded.
import { createRequire } from 'node:module'
import { join } from 'node:path'
import { pathToFileURL } from 'node:url'

const [modules, file] = process.argv.slice(2)
if (!modules || !file) {
  console.error('usage: node copcjs_read.mjs NODE_MODULES FILE')
  process.exit(2)
}
const require = createRequire(join(modules, 'package.json'))
const lib = await import(pathToFileURL(require.resolve('copc')).href)
const { Copc } = lib.Copc ? lib : lib.default

const copc = await Copc.create(file)
const { cube, spacing, rootHierarchyPage, gpsTimeRange } = copc.info
const nodes = {}
const pages = [rootHierarchyPage]
while (pages.length > 0) {
  const page = await Copc.loadHierarchyPage(file, pages.shift())
  Object.assign(nodes, page.nodes)
  pages.push(...Object.values(page.pages))
}
const keyOrder = (k) => k.split('-').map(Number)
const keys = Object.keys(nodes)
  .filter((k) => nodes[k].pointCount > 0)
  .sort((a, b) => {
    const x = keyOrder(a), y = keyOrder(b)
    for (let i = 0; i < 4; ++i) if (x[i] !== y[i]) return x[i] - y[i]
    return 0
  })

const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity]
const sum = [0n, 0n, 0n], roles = [0, 0, 0]
let points = 0
const counts = {}
for (const key of keys) {
  const view = await Copc.loadPointDataView(file, copc, nodes[key])
  if (view.pointCount !== nodes[key].pointCount)
    throw new Error(`node ${key}: ${view.pointCount} points decoded, ${nodes[key].pointCount} in the hierarchy`)
  counts[key] = view.pointCount
  const get = ['X', 'Y', 'Z'].map((d) => view.getter(d))
  const cls = view.getter('Classification')
  // A node's sums stay exact in doubles (below 2^53 mm); the file's add up as BigInts.
  const nodeSum = [0, 0, 0]
  for (let i = 0; i < view.pointCount; ++i) {
    for (let k = 0; k < 3; ++k) {
      const mm = Math.round(get[k](i) * 1000)
      if (mm < min[k]) min[k] = mm
      if (mm > max[k]) max[k] = mm
      nodeSum[k] += mm
    }
    const c = cls(i)
    ++roles[c === 2 ? 0 : c === 64 ? 2 : 1]
    ++points
  }
  for (let k = 0; k < 3; ++k) {
    if (!Number.isSafeInteger(nodeSum[k])) throw new Error(`node ${key}: the coordinate sums exceed 2^53 mm`)
    sum[k] += BigInt(nodeSum[k])
  }
}
console.log(JSON.stringify({
  info: {
    center: [0, 1, 2].map((k) => (cube[k] + cube[k + 3]) / 2),
    halfsize: (cube[3] - cube[0]) / 2,
    spacing,
    root_hier_offset: rootHierarchyPage.pageOffset,
    root_hier_size: rootHierarchyPage.pageLength,
    gpstime: gpsTimeRange,
  },
  node_count: keys.length,
  nodes: counts,
  points,
  min_mm: min,
  max_mm: max,
  sum_mm: sum.map(String),
  roles,
}))
