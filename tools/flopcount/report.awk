# SPDX-License-Identifier: MIT
#
# report.awk -v mode=text|json|md|rows  DRIVER_OUT WINDOWS BUDGET FOOTPRINT
#
# Combines the driver's fcop lines (DRIVER_OUT), the counted windows of
# count.sh (WINDOWS), the FLOP budget file and the footprint records of
# footprint.sh into the text table, the JSON document or the Markdown
# tables of docs/cost.md. Checks the budgets: prints "BUDGET FAIL ..." on
# stderr and exits 1 when a count exceeds its budget.
#
# Definitions (docs/cost.md): add = additions + subtractions; FLOPs =
# add + mul + div + sqrt (+ 2 per fused or chained multiply-add, none with
# -std=c99); fp_arith = every VFP arithmetic instruction (FLOPs + vabs/vneg).

function fmt(x) { return (x == int(x)) ? sprintf("%d", x) : sprintf("%.2f", x) }
function fmt1(x) { return (x == int(x)) ? sprintf("%d", x) : sprintf("%.1f", x) }
function jstr(s) { gsub(/\\/, "\\\\", s); gsub(/"/, "\\\"", s); return "\"" s "\"" }

BEGIN {
    nk = split("insns cyc add sub mul div sqrt fma mla absneg cmp cvt fpmov fpldst f64", key, " ")
    chapter_incr = 123
}
FILENAME == ARGV[1] {
    if ($1 == "fcop") { nop++; opname[nop] = $2; opdiv[nop] = $3; opn[nop] = $4; opfn[nop] = $5 }
    else if ($1 == "fcinfo") info[$2] = $3
    else if ($1 == "fcfail") failed[$2] = $3
    next
}
FILENAME == ARGV[2] {
    if ($1 == "win") { for (i = 1; i <= nk; i++) w[$2, key[i]] = $(i + 2); nwin = $2 + 1 }
    next
}
FILENAME == ARGV[3] {
    sub(/#.*/, "")
    if ($1 == "insns" && NF >= 3) { nib++; ibname[nib] = $2; ibmax[$2] = $3; ibkey[nib] = "insns"; next }
    if ($1 == "cycles" && NF >= 3) { nib++; ibname[nib] = $2; ibmax[$2 ",c"] = $3; ibkey[nib] = "cyc"; next }
    if (NF >= 2) { nb++; bname[nb] = $1; bmax[$1] = $2; bneeds[$1] = (NF >= 3) ? $3 : "" }
    next
}
FILENAME == ARGV[4] {
    if ($1 == "stack") { stk_os[$2] = $3; stk_o2[$2] = $4 }
    else if ($1 == "code") { ncode++; cmod[ncode] = $2; cdos[$2] = $3; co2[$2] = $4 }
    else if ($1 == "code_total") { ctot_os = $2; ctot_o2 = $3 }
    else if ($1 == "struct") { nst++; sname[nst] = $2; ssize[$2] = $3 }
    else if ($1 == "check") { nchk++; chk[nchk] = $0 }
    next
}
END {
    # ---- per-operation figures ----
    wi = 0
    for (o = 1; o <= nop; o++) {
        n = opname[o]
        for (i = 1; i <= nk; i++) {
            v = w[wi, key[i]]
            if (opn[o] == 2) v -= w[wi + 1, key[i]]
            val[n, key[i]] = v / opdiv[o]
        }
        wi += opn[o]
        val[n, "addsub"] = val[n, "add"] + val[n, "sub"]
        val[n, "flops"] = val[n, "addsub"] + val[n, "mul"] + val[n, "div"] + val[n, "sqrt"] \
                          + 2 * (val[n, "fma"] + val[n, "mla"])
        val[n, "fparith"] = val[n, "flops"] - (val[n, "fma"] + val[n, "mla"]) + val[n, "absneg"]
        # 2 decimals is the precision of every printed and budgeted figure
        for (i = 1; i <= nk; i++) val[n, key[i]] = int(val[n, key[i]] * 100 + 0.5) / 100
        val[n, "flops"] = int(val[n, "flops"] * 100 + 0.5) / 100
        val[n, "addsub"] = int(val[n, "addsub"] * 100 + 0.5) / 100
        val[n, "fparith"] = int(val[n, "fparith"] * 100 + 0.5) / 100
        have[n] = 1
    }
    if (wi != nwin) {
        printf "report: %d windows counted, %d expected (driver output and trace disagree)\n", nwin, wi > "/dev/stderr"
        exit 2
    }
    # Jacobi per sweep: a sweep is 3 rotations; jacobi_rotation is one.
    if (have["jacobi_rotation"]) per_sweep = 3 * val["jacobi_rotation", "flops"]
    if (have["jacobi_eig"]) rotations = val["jacobi_eig", "sqrt"] / 2

    # ---- budgets ----
    bad = 0
    for (b = 1; b <= nb; b++) {
        n = bname[b]
        if (!have[n]) {
            if (bneeds[n] != "" && info["have_" bneeds[n]] == "0") { bstat[n] = "pending"; continue }
            bstat[n] = "MISSING"; bad = 1
            printf "BUDGET FAIL %s: budgeted (%s FLOPs) but not measured\n", n, bmax[n] > "/dev/stderr"
            continue
        }
        if (val[n, "flops"] > bmax[n] + 0) {
            bstat[n] = "OVER"; bad = 1
            printf "BUDGET FAIL %s: %s FLOPs > budget %s\n", n, fmt(val[n, "flops"]), bmax[n] > "/dev/stderr"
        } else bstat[n] = "ok"
    }
    # instruction budgets ("insns NAME MAX" lines): M4F instructions, exact counts
    # ("cycles NAME MAX" lines: the cycle model's estimate)
    for (b = 1; b <= nib; b++) {
        n = ibname[b]
        lim = (ibkey[b] == "cyc") ? ibmax[n ",c"] : ibmax[n]
        what = (ibkey[b] == "cyc") ? "estimated M4F cycles" : "M4F instructions"
        if (!have[n]) {
            bad = 1
            printf "BUDGET FAIL %s: %s budget %s but not measured\n", n, what, lim > "/dev/stderr"
        } else if (val[n, ibkey[b]] > lim + 0) {
            bad = 1
            printf "BUDGET FAIL %s: %s %s > budget %s\n", n, what, fmt(val[n, ibkey[b]]), lim > "/dev/stderr"
        }
    }
    for (n in failed) { bad = 1; printf "FAIL %s returned status %s\n", n, failed[n] > "/dev/stderr" }

    # ---- the chapter's claims ----
    incr = have["incremental_update"] ? val["incremental_update", "flops"] : -1
    gd = have["batch_per_point"] ? val["batch_per_point", "flops"] : -1
    ratio_ch = (gd > 0) ? chapter_incr / gd : -1
    ratio_me = (gd > 0 && incr >= 0) ? incr / gd : -1

    if (mode == "rows") {
        # one record per operation and per footprint total (tools/flopcount/cores.sh)
        for (o = 1; o <= nop; o++) {
            n = opname[o]
            printf "op %s %s %s %s %s %s\n", n, fmt(val[n, "flops"]), fmt(val[n, "insns"]), \
                fmt(val[n, "fparith"]), (opfn[o] in stk_o2) ? stk_o2[opfn[o]] : "-", \
                (opfn[o] in stk_os) ? stk_os[opfn[o]] : "-"
        }
        printf "code_total %s %s\n", ctot_os, ctot_o2
        for (sf in stk_o2) printf "stack %s %s %s\n", sf, stk_o2[sf], stk_os[sf]
    } else if (mode == "json") {
        printf "{\n  \"tool\": \"sfit flopcount\",\n"
        printf "  \"target\": \"Cortex-M4F (QEMU mps2-an386), arm-none-eabi-gcc -O2 -std=c99\",\n"
        printf "  \"config\": {\"sum_block\": %s, \"samples\": %s},\n", info["sum_block"], info["npts"]
        printf "  \"operations\": [\n"
        for (o = 1; o <= nop; o++) {
            n = opname[o]
            printf "    {\"name\": %s, \"function\": %s, \"flops\": %s, \"add\": %s, \"sub\": %s, \"mul\": %s, \"div\": %s, \"sqrt\": %s, ", \
                jstr(n), jstr(opfn[o]), fmt(val[n, "flops"]), fmt(val[n, "addsub"]), fmt(val[n, "sub"]), fmt(val[n, "mul"]), \
                fmt(val[n, "div"]), fmt(val[n, "sqrt"])
            printf "\"fma\": %s, \"cmp\": %s, \"cvt\": %s, \"absneg\": %s, \"f64\": %s, \"insns\": %s, \"fp_arith\": %s, \"cycles_est\": %s", \
                fmt(val[n, "fma"] + val[n, "mla"]), fmt(val[n, "cmp"]), fmt(val[n, "cvt"]), fmt(val[n, "absneg"]), fmt(val[n, "f64"]), \
                fmt(val[n, "insns"]), fmt(val[n, "fparith"]), fmt(val[n, "cyc"])
            if (opfn[o] in stk_o2) printf ", \"stack_O2\": %s, \"stack_Os\": %s", stk_o2[opfn[o]], stk_os[opfn[o]]
            if (n in bmax) printf ", \"budget\": %s", bmax[n]
            if (n == "jacobi_eig") printf ", \"rotations\": %s, \"per_sweep\": %s", fmt(rotations), fmt(per_sweep)
            printf "}%s\n", (o < nop) ? "," : ""
        }
        printf "  ],\n  \"chapter\": {\"incremental_update_claim\": 123, \"incremental_update\": %s, \"batch_gdke_per_point\": %s, ", \
            (incr >= 0 ? fmt(incr) : "null"), (gd >= 0 ? fmt(gd) : "null")
        printf "\"ratio_claimed\": 4, \"ratio_chapter_flops_over_measured_batch\": %s, \"ratio_measured\": %s},\n", \
            (ratio_ch >= 0 ? sprintf("%.2f", ratio_ch) : "null"), (ratio_me >= 0 ? sprintf("%.2f", ratio_me) : "null")
        printf "  \"budget_ok\": %s\n}\n", bad ? "false" : "true"
    } else if (mode == "md") {
        print "Measured by `tools/flopcount/run.sh --update-docs` (Cortex-M4F, QEMU"
        print "mps2-an386, arm-none-eabi-gcc -O2 -std=c99; SFIT_SUM_BLOCK = " info["sum_block"] ")."
        print "FLOPs and instructions are exact counts; **cycles are an estimate** from"
        print "the cycle model below, not a measurement. Stack: worst case of the public"
        print "function (static call-graph bound, -O2 / -Os)."
        print ""
        print "| operation | FLOPs | add/sub | mul | div | sqrt | cmp | cvt | M4F instructions | FP arith. instr. | est. cycles | stack O2/Os (B) | FLOP budget |"
        print "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
        for (o = 1; o <= nop; o++) {
            n = opname[o]
            printf "| `%s` | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", n, fmt(val[n, "flops"]), \
                fmt(val[n, "addsub"]), fmt(val[n, "mul"]), fmt(val[n, "div"]), fmt(val[n, "sqrt"]), fmt(val[n, "cmp"]), \
                fmt(val[n, "cvt"]), fmt1(val[n, "insns"]), fmt1(val[n, "fparith"]), fmt1(val[n, "cyc"]), \
                (opfn[o] in stk_o2) ? stk_o2[opfn[o]] "/" stk_os[opfn[o]] : "-", (n in bmax) ? bmax[n] : "-"
        }
        for (b = 1; b <= nb; b++) if (bstat[bname[b]] == "pending")
            printf "| `%s` | (module not built yet) | | | | | | | | | | | %s |\n", bname[b], bmax[bname[b]]
        print ""
        printf "Jacobi: %s rotations on the 45-degree cap covariance (%s FLOPs in all); one rotation costs %s FLOPs, a full sweep (3 rotations) %s.\n", \
            fmt(rotations), fmt(val["jacobi_eig", "flops"]), fmt(val["jacobi_rotation", "flops"]), fmt(per_sweep)
        print ""
        print "The chapter's cost claims, measured:"
        print ""
        print "| claim | chapter | measured |"
        print "|---|---:|---:|"
        printf "| FLOPs per incremental update, D = 3 (eq. 233) | 123 | %s |\n", (incr >= 0 ? fmt(incr) : "pending (no sfit_incr module)")
        printf "| batch GDKE, FLOPs per point (amortised moments add) | - | %s (%s) |\n", fmt(gd), fmt(val["moments_add", "flops"])
        printf "| incremental / batch GDKE per point (\"about four times\") | 4 | %s |\n", \
            (ratio_me >= 0 ? sprintf("%.2f", ratio_me) : sprintf("pending; 123 / %s = %.2f", fmt(gd), ratio_ch))
        printf "| moments add, FLOPs per sample (budget <= 30) | - | %s amortised, %s per call without a block merge |\n", \
            fmt(val["moments_add", "flops"]), fmt(val["moments_add_call", "flops"])
        print ""
        print "Footprint (arm-none-eabi-gcc 12, Thumb-2, .text + .rodata per module; no .data/.bss):"
        print ""
        print "| module | -Os (B) | -O2 (B) |"
        print "|---|---:|---:|"
        for (c = 1; c <= ncode; c++) printf "| `%s` | %s | %s |\n", cmod[c], cdos[cmod[c]], co2[cmod[c]]
        printf "| **total** | **%s** | **%s** |\n", ctot_os, ctot_o2
        print ""
        print "| struct | bytes |"
        print "|---|---:|"
        for (s = 1; s <= nst; s++) printf "| `%s` | %s |\n", sname[s], ssize[sname[s]]
        print ""
        for (c = 1; c <= nchk; c++) { split(chk[c], f, " "); if (f[2] != "budget") { line = chk[c]; sub(/^check /, "", line); printf "- %s\n", line } }
    } else {
        printf "sfit flopcount: Cortex-M4F (QEMU mps2-an386), arm-none-eabi-gcc -O2 -std=c99, SFIT_SUM_BLOCK=%s\n", info["sum_block"]
        printf "FLOPs = add/sub + mul + div + sqrt; cycles are an ESTIMATE (docs/cost.md cycle model)\n\n"
        printf "%-24s %8s %8s %7s %6s %5s %5s %5s %9s %8s %9s %9s %7s\n", "operation", "FLOPs", "add/sub", "mul", "div", "sqrt", \
            "cmp", "cvt", "insns", "fp_arith", "cyc(est)", "stack O2", "budget"
        for (o = 1; o <= nop; o++) {
            n = opname[o]
            printf "%-24s %8s %8s %7s %6s %5s %5s %5s %9s %8s %9s %9s %7s %s\n", n, fmt(val[n, "flops"]), fmt(val[n, "addsub"]), \
                fmt(val[n, "mul"]), fmt(val[n, "div"]), fmt(val[n, "sqrt"]), fmt(val[n, "cmp"]), fmt(val[n, "cvt"]), \
                fmt1(val[n, "insns"]), fmt1(val[n, "fparith"]), fmt1(val[n, "cyc"]), (opfn[o] in stk_o2) ? stk_o2[opfn[o]] : "-", \
                (n in bmax) ? bmax[n] : "-", (n in bstat && bstat[n] != "ok") ? bstat[n] : ""
        }
        for (b = 1; b <= nb; b++) if (bstat[bname[b]] == "pending")
            printf "%-24s %8s %60s %7s pending (module not built)\n", bname[b], "-", "", bmax[bname[b]]
        printf "\nJacobi on the 45-degree cap covariance: %s rotations, %s FLOPs; per rotation %s, per sweep (3 rotations) %s\n", \
            fmt(rotations), fmt(val["jacobi_eig", "flops"]), fmt(val["jacobi_rotation", "flops"]), fmt(per_sweep)
        printf "\nChapter claims:\n"
        printf "  incremental update, D = 3 (eq. 233): chapter 123 FLOPs, measured %s\n", (incr >= 0 ? fmt(incr) : "pending (no sfit_incr module)")
        printf "  batch GDKE per point: measured %s FLOPs (moments add amortised %s, per call %s)\n", fmt(gd), \
            fmt(val["moments_add", "flops"]), fmt(val["moments_add_call", "flops"])
        if (ratio_me >= 0) printf "  incremental / batch per point: measured %.2f (chapter: \"about four times\")\n", ratio_me
        else printf "  incremental / batch per point: chapter's 123 / measured %s = %.2f (chapter: \"about four times\")\n", fmt(gd), ratio_ch
        if (ncode > 0) {
            printf "\nFootprint: code %s B (-Os), %s B (-O2)\n", ctot_os, ctot_o2
            for (c = 1; c <= nchk; c++) print "  " chk[c]
        }
        printf "\nbudget: %s\n", bad ? "FAILED" : "ok"
    }
    exit bad
}
