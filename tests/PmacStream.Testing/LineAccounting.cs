namespace PmacStream.Testing;

/// <summary>Lost, repeated and reordered program lines, for motion and non-motion lines apart.</summary>
public readonly record struct LineCounts(int Lost, int Repeated, int Reordered)
{
    public static LineCounts operator +(LineCounts a, LineCounts b) => new(a.Lost + b.Lost, a.Repeated + b.Repeated, a.Reordered + b.Reordered);

    public bool Exact => Lost == 0 && Repeated == 0 && Reordered == 0;

    public override string ToString() => $"{Lost} lost, {Repeated} repeated, {Reordered} reordered";
}

/// <summary>
/// Compares the program lines the controller executed with the lines of the program, in order. Lost and repeated are
/// multiset differences by text; reordered counts lines present the right number of times but out of order (the
/// lines not on a longest common subsequence once lost ones are discounted).
/// </summary>
public static class LineAccounting
{
    public static (LineCounts Motion, LineCounts NonMotion) Compare(IReadOnlyList<string> expected, IReadOnlyList<string> executed, Func<string, bool> isMotion)
    {
        var e = expected.Select(Norm).ToList();
        var x = executed.Select(Norm).ToList();
        return (Count(e.Where(isMotion).ToList(), x.Where(isMotion).ToList()), Count(e.Where(t => !isMotion(t)).ToList(), x.Where(t => !isMotion(t)).ToList()));
    }

    public static LineCounts Count(IReadOnlyList<string> expected, IReadOnlyList<string> executed)
    {
        var want = expected.GroupBy(t => t).ToDictionary(g => g.Key, g => g.Count());
        var got = executed.GroupBy(t => t).ToDictionary(g => g.Key, g => g.Count());
        var lost = want.Sum(kv => Math.Max(0, kv.Value - got.GetValueOrDefault(kv.Key)));
        var repeated = got.Sum(kv => Math.Max(0, kv.Value - want.GetValueOrDefault(kv.Key)));
        var lcs = Lcs(expected, executed);
        return new LineCounts(lost, repeated, Math.Max(0, expected.Count - lost - lcs));
    }

    private static string Norm(string t) => t.Trim().ToUpperInvariant();

    private static int Lcs(IReadOnlyList<string> a, IReadOnlyList<string> b)
    {
        var prev = new int[b.Count + 1];
        var cur = new int[b.Count + 1];
        for (var i = 1; i <= a.Count; i++)
        {
            for (var j = 1; j <= b.Count; j++)
            {
                cur[j] = a[i - 1] == b[j - 1] ? prev[j - 1] + 1 : Math.Max(prev[j], cur[j - 1]);
            }

            (prev, cur) = (cur, prev);
        }

        return prev[b.Count];
    }
}
