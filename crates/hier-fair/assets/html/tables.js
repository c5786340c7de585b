// hier-fair's report tables: the links (G0, G1, G2 along, across and at the vertices, before and
// after, target, verdict) and the surfaces (deviation, energy, peak curvature, the comb's peak across
// the linked sides, curvature extrema, the fairness verdict,
// net, time), sortable; a click selects in the 3D view. Licence: that of hier-fair.
function hierFairTables(D, MM, fmt, select) {
  'use strict';
  var tol = D.tolerances;
  var fair = D.kind === 'fair';
  var problems = (fair && D.report && D.report.problems) || [];

  // a link's verdict: met; a named conflict; worse than the input; or unmet
  function status(k, before, after, met) {
    if (met) return 'met';
    var label = D.links[k].label;
    if (problems.some(function (p) { return p.kind === 'conflict' && p.link === label; })) return 'conflict';
    if (before && after && (after.g0 > before.g0 + tol.g0 ||
        (after.g1_deg || 0) > (before.g1_deg || 0) + tol.g1_deg)) return 'worse';
    return 'unmet';
  }
  function meets(m, target) {
    if (!m) return false;
    if (m.g0 > tol.g0) return false;
    if (target !== 'G0' && m.g1_deg !== null && m.g1_deg > tol.g1_deg) return false;
    return !(target === 'G2' && m.g2_rel !== null && m.g2_rel > tol.g2_rel);
  }

  var linkRows = D.links.map(function (l, k) {
    var before, after, met;
    if (fair) {
      var r = D.report.links[k];
      before = r.before; after = r.after; met = r.met;
    } else {
      before = D.checks ? D.checks.links[k] : null; after = null; met = meets(before, l.target);
    }
    var m = fair ? after : before;
    var row = { index: k, cells: [l.label, l.target] };
    function both(f) { row.cells.push(f(before)); if (fair) row.cells.push(f(after)); }
    both(function (x) { return x ? x.g0 * MM : null; });
    both(function (x) { return x ? x.g1_deg : null; });
    both(function (x) { return x ? x.g2_rel : null; });
    both(function (x) { return x ? x.g2_rel_across : null; });
    row.cells.push(m ? m.g1_deg_vertex : null, m ? m.g2_rel_vertex : null);
    row.cells.push(status(k, before, after, met));
    return row;
  });
  var w = fair ? [' before', ' after'] : [''];
  function heads(name) { return w.map(function (s) { return name + s; }); }
  var linkHeads = ['link', 'target'].concat(heads('G0 gap (mm)'), heads('G1 angle (°)'),
    heads('G2 rel.'), heads('G2 rel. across'), ['vertex G1 (°)', 'vertex G2 rel.', 'verdict']);
  table('hf-links', linkHeads, linkRows, function (row) { select(D.links[row.index].slave, row.index, true); });

  var bySurface = {};
  if (fair && D.report) D.report.surfaces.forEach(function (s) { bySurface[s.name] = s; });
  var surfaceRows = D.surfaces.map(function (s, k) {
    var fb = s.fairness_before, fa = s.fairness_after, r = bySurface[s.name];
    var cells = [s.name, s.role];
    if (fair) cells.push(r ? r.method : null, r ? r.max_deviation * MM : null, r ? r.tolerance * MM : null);
    function both(f) { cells.push(f(fb)); if (fair) cells.push(fa ? f(fa) : null); }
    both(function (x) { return x.peak_curvature / MM; });
    both(function (x) { return x.cross_peak === null ? null : x.cross_peak / MM; });
    both(function (x) { return x.cross_extrema; });
    both(function (x) { return x.energy; });
    both(function (x) { return x.net.join(' × '); });
    cells.push(fb.degree.join(' × '));
    if (fair) cells.push(r ? r.seconds : null);
    // the verdict against the input (report.json's `fairness`): "fair", or what fails
    if (fair) cells.push(r && r.fairness ? (r.fairness.fair ? 'fair' : r.fairness.faults.join('; ')) : null);
    return { index: k, cells: cells };
  });
  var surfaceHeads = ['surface', 'role'].concat(fair ? ['method', 'deviation (mm)', 'tolerance (mm)'] : [],
    heads('peak curvature (1/mm)'), heads('comb peak (1/mm)'), heads('extrema'), heads('energy'),
    heads('net'), ['degree'], fair ? ['time (s)', 'fairness'] : []);
  table('hf-surfaces', surfaceHeads, surfaceRows, function (row) { select(row.index, -1, true); });

  var summary = document.getElementById('hf-summary');
  var counts = { met: 0, conflict: 0, worse: 0, unmet: 0 };
  linkRows.forEach(function (r) { counts[r.cells[r.cells.length - 1]]++; });
  summary.textContent = counts.met + ' of ' + linkRows.length + ' links met' +
    (counts.conflict ? ', ' + counts.conflict + ' named conflicts' : '') +
    (counts.worse ? ', ' + counts.worse + ' worse than the input' : '') +
    (counts.unmet ? ', ' + counts.unmet + ' unmet' : '') +
    (fair && D.report ? ' · ' + fmt(D.report.seconds_total) + ' s' : '');

  function table(id, heads, rows, onClick) {
    var t = document.getElementById(id), order = { col: -1, dir: 1 };
    var thead = t.createTHead(), tbody = t.createTBody(), tr = thead.insertRow();
    heads.forEach(function (h, c) {
      var th = document.createElement('th');
      th.textContent = h;
      th.addEventListener('click', function () {
        order.dir = order.col === c ? -order.dir : 1;
        order.col = c;
        rows.sort(function (a, b) { return order.dir * compare(a.cells[c], b.cells[c]); });
        fill();
      });
      tr.appendChild(th);
    });
    function fill() {
      tbody.textContent = '';
      rows.forEach(function (row) {
        var r = tbody.insertRow();
        r.dataset.index = row.index;
        row.cells.forEach(function (v) {
          var td = r.insertCell();
          td.textContent = typeof v === 'number' ? fmt(v) : v === null || v === undefined ? '–' : v;
          if (v === 'met' || v === 'unmet' || v === 'worse' || v === 'conflict') td.className = v;
        });
        r.addEventListener('click', function () { onClick(row); });
      });
    }
    fill();
  }
  function compare(a, b) {
    var na = a === null || a === undefined, nb = b === null || b === undefined;
    if (na || nb) return na === nb ? 0 : na ? 1 : -1;
    if (typeof a === 'number' && typeof b === 'number') return a - b;
    return String(a).localeCompare(String(b), undefined, { numeric: true });
  }
}
