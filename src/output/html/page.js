"use strict";
// Sortable tables: a click on a heading sorts the rows by that column (numbers by their
// value, the rest as text); a second click reverses the order.
(function () {
  for (const table of document.querySelectorAll("table.sortable")) {
    const heads = table.tHead.rows[0].cells;
    for (let c = 0; c < heads.length; c++) {
      heads[c].addEventListener("click", function () {
        const desc = heads[c].classList.contains("asc");
        for (const h of heads) h.classList.remove("asc", "desc");
        heads[c].classList.add(desc ? "desc" : "asc");
        const body = table.tBodies[0];
        const rows = Array.from(body.rows);
        const key = function (r) {
          const cell = r.cells[c];
          const v = cell.getAttribute("data-v");
          if (v !== null) return v === "" ? NaN : parseFloat(v);
          return cell.textContent;
        };
        rows.sort(function (a, b) {
          const x = key(a), y = key(b);
          let o;
          if (typeof x === "number" && typeof y === "number") {
            if (isNaN(x) && isNaN(y)) o = 0;
            else if (isNaN(x)) o = 1;
            else if (isNaN(y)) o = -1;
            else o = x - y;
          } else {
            o = String(x).localeCompare(String(y));
          }
          if (o === 0) o = a.rowIndex - b.rowIndex;
          return desc ? -o : o;
        });
        for (const r of rows) body.appendChild(r);
      });
    }
  }
})();
