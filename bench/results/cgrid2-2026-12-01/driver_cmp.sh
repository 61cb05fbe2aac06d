#!/bin/bash
# usage: cmp.sh n reps rounds binA binB ; prints min-of-mins and median-of-medians per binary
n=$1; reps=$2; rounds=$3; extra="$4"; shift 4
for r in $(seq $rounds); do for b in "$@"; do echo "$b $(./$b $n $reps $extra)"; done; done > /tmp/cmp_$$.txt
for b in "$@"; do
  grep "^$b " /tmp/cmp_$$.txt | python3 -c "
import sys,re,statistics
mins=[];meds=[];dmins=[]
for l in sys.stdin:
  m=re.search(r'ns/obj median=([\d.]+) min=([\d.]+)',l); meds.append(float(m.group(1))); mins.append(float(m.group(2)))
  d=re.search(r'discretize median=([\d.]+) min=([\d.]+)',l); dmins.append(float(d.group(2)))
print('$b', 'min', min(mins), 'median-of-medians', statistics.median(meds), 'median-of-mins', statistics.median(mins), 'discretize min', min(dmins))
"
done
