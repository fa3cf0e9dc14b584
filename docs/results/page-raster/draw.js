// The scene of the raster pages (measure-page-raster.sh): about what the view's
// page draws for keepaway_pass (17 places, 25 transitions, 50 arcs, their labels,
// a 3-row table, two 300-point curves), a new one each second (seed).
function scene(seed) {
  const r = (i) => ((Math.sin(i * 12.9898 + seed * 78.233) * 43758.5453) % 1 + 1) % 1;
  const places = [], trans = [], edges = [];
  for (let i = 0; i < 17; i++) places.push({x: 60 + (i % 6) * 130, y: 120 + Math.floor(i / 6) * 150, tok: r(i) > 0.6 ? 1 : 0, label: 'place_' + i});
  for (let i = 0; i < 25; i++) trans.push({x: 120 + (i % 7) * 110, y: 90 + Math.floor(i / 7) * 110, label: '[cond ' + i + ']', red: r(i + 100) > 0.8});
  for (let i = 0; i < 50; i++) edges.push([places[i % 17], trans[(i * 7) % 25]]);
  const curve = [], ret = [];
  for (let i = 0; i < 300; i++) { curve.push(r(i + 200) * 50); ret.push(r(i + 600) * 30 + 10); }
  const rows = [['ball', 'Hold.start', (r(1) * 10).toFixed(3), Math.floor(r(2) * 900)], ['', 'Pass1.start', (r(3) * 10).toFixed(3), Math.floor(r(4) * 900)], ['', 'Pass2.start', (r(5) * 10).toFixed(3), Math.floor(r(6) * 900)]];
  return {places, trans, edges, curve, ret, rows, text: 'episode ' + seed + ', step ' + Math.floor(r(7) * 40) + ': Lane1Open, Lane2Open, TakerFar'};
}
function paint(ctx, s) {
  ctx.fillStyle = '#f5f4ee'; ctx.fillRect(0, 0, 1400, 900);
  ctx.fillStyle = '#fff'; ctx.fillRect(10, 50, 880, 620); ctx.fillRect(905, 50, 440, 220); ctx.fillRect(905, 285, 440, 385);
  ctx.strokeStyle = '#777'; ctx.lineWidth = 1;
  for (const [p, t] of s.edges) { ctx.beginPath(); ctx.moveTo(p.x, p.y); ctx.quadraticCurveTo((p.x + t.x) / 2, p.y + 40, t.x, t.y); ctx.stroke(); }
  ctx.font = '11px sans-serif'; ctx.textAlign = 'center';
  for (const p of s.places) { ctx.beginPath(); ctx.arc(p.x, p.y, 15, 0, 7); ctx.fillStyle = p.tok ? '#fcd34d' : '#fff'; ctx.fill(); ctx.lineWidth = 2; ctx.strokeStyle = '#222'; ctx.stroke(); ctx.fillStyle = '#222'; ctx.fillText(p.label, p.x, p.y + 28); if (p.tok) ctx.fillText('1', p.x, p.y + 4); }
  for (const t of s.trans) { ctx.fillStyle = t.red ? '#e33' : '#445'; ctx.fillRect(t.x - 3, t.y - 15, 6, 30); ctx.fillStyle = '#222'; ctx.fillText(t.label, t.x, t.y - 20); }
  ctx.textAlign = 'left'; ctx.font = '12px monospace'; ctx.fillText(s.text, 22, 620);
  ctx.font = '12px sans-serif';
  s.rows.forEach((row, i) => row.forEach((c, j) => ctx.fillText(String(c), 930 + j * 100, 110 + i * 20)));
  ctx.lineWidth = 1.5;
  for (const [pts, col] of [[s.curve, '#2563eb'], [s.ret, '#d97706']]) { ctx.beginPath(); ctx.strokeStyle = col; pts.forEach((v, i) => { const x = 970 + i * 1.2, y = 500 - v * 3; i ? ctx.lineTo(x, y) : ctx.moveTo(x, y); }); ctx.stroke(); }
}
