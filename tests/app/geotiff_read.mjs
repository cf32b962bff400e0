// geotiff_read.mjs NODE_MODULES FILE.tif [FILE.asc]: reads a GeoTIFF with geotiff.js (the
// npm package `geotiff`, an independent reader) and prints, as one JSON object, what a
// GIS takes from it: its size, origin (top-left corner), resolution, nodata value, GeoTIFF
// keys, sample format, compression, predictor, strip count and whether it is a BigTIFF. With an ESRI ASCII grid
// beside it, also compares every cell: the largest difference between the two where both
// have a height, and the cells where one has the nodata value and the other not.
import { createRequire } from 'node:module'
import { readFileSync } from 'node:fs'
import { join } from 'node:path'
import { pathToFileURL } from 'node:url'

const [modules, file, asc] = process.argv.slice(2)
if (!modules || !file) {
  console.error('usage: node geotiff_read.mjs NODE_MODULES FILE.tif [FILE.asc]')
  process.exit(2)
}
const require = createRequire(join(modules, 'package.json'))
const { fromArrayBuffer } = await import(pathToFileURL(require.resolve('geotiff')).href)

const bytes = readFileSync(file)
const tiff = await fromArrayBuffer(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength))
const image = await tiff.getImage()
const width = image.getWidth()
const height = image.getHeight()
const [band] = await image.readRasters()
const out = {
  width,
  height,
  bands: image.getSamplesPerPixel(),
  bits: image.getBitsPerSample(),
  sample_format: image.getSampleFormat(),
  origin: image.getOrigin(),
  resolution: image.getResolution(),
  nodata: image.getGDALNoData(),
  geokeys: image.getGeoKeys(),
  array: band.constructor.name,
  compression: image.fileDirectory.getValue('Compression') ?? 1,
  predictor: image.fileDirectory.getValue('Predictor') ?? 1,
  strips: image.fileDirectory.getValue('StripOffsets').length,
  bigtiff: tiff.bigTiff,
}
if (asc) {
  const lines = readFileSync(asc, 'utf8').split('\n')
  const head = {}
  for (const line of lines.slice(0, 6)) {
    const [key, value] = line.trim().split(/\s+/)
    head[key.toLowerCase()] = Number(value)
  }
  const cells = lines.slice(6).join(' ').trim().split(/\s+/).map(Number)
  let largest = 0
  let nodataMismatch = 0
  let heights = 0
  for (let k = 0; k < cells.length; ++k) {
    const a = cells[k]
    const t = band[k]
    if ((a === head.nodata_value) !== (t === out.nodata)) ++nodataMismatch
    else if (a !== head.nodata_value) {
      largest = Math.max(largest, Math.abs(a - t))
      ++heights
    }
  }
  out.asc = {
    columns: head.ncols,
    rows: head.nrows,
    west: head.xllcorner,
    north: head.yllcorner + head.nrows * head.cellsize,
    cell: head.cellsize,
    cells: cells.length,
    heights,
    largest_difference: largest,
    nodata_mismatch: nodataMismatch,
  }
}
console.log(JSON.stringify(out))
