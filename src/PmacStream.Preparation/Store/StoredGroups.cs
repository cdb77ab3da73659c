using System.Globalization;
using System.Text;
using System.Text.Json;
using PmacStream.GCode;

namespace PmacStream.Preparation.Store;

/// <summary>
/// How a stored program's modal groups map to the store: the first nine G groups in the columns GA..GI, the first
/// three M groups in MA..MC (the store's first layout), any further groups of the profile as JSON in
/// <c>group_states</c>, once per distinct state (a block names its state in <c>group_state</c>: states change far more
/// rarely than blocks), and the group names in <c>programs.groups</c>.
/// </summary>
public sealed class StoredGroups
{
    private const int GColumns = 9;
    private const int MColumns = 3;

    private readonly IReadOnlyDictionary<long, string> _states;

    private StoredGroups(IReadOnlyList<string> g, IReadOnlyList<string> m, IReadOnlyDictionary<long, string>? states = null)
    {
        GNames = g;
        MNames = m;
        _states = states ?? new Dictionary<long, string>();
    }

    /// <summary>Names of the program's G groups, in store order.</summary>
    public IReadOnlyList<string> GNames { get; }

    /// <summary>Names of the program's M groups, in store order.</summary>
    public IReadOnlyList<string> MNames { get; }

    /// <summary>The groups of a program stored without them: paper-24g7m's GA..GI and MA..MC.</summary>
    public static StoredGroups Paper { get; } = new(MachineProfile.GGroupNames, MachineProfile.MGroupNames);

    /// <summary>The <c>programs.groups</c> text of a profile: <c>{"G":["01","06",...],"M":["stop",...]}</c>.</summary>
    public static string Describe(MachineProfile profile) =>
        JsonSerializer.Serialize(
            new Dictionary<string, string[]> { ["G"] = profile.GGroups.Select(g => g.Name).ToArray(), ["M"] = profile.MGroups.Select(g => g.Name).ToArray() },
            StoredGroupsJson.Default.DictionaryStringStringArray);

    /// <summary>
    /// Reads <c>programs.groups</c> and the program's <c>group_states</c> (by id); null names (a program stored before
    /// groups were recorded) give <see cref="Paper"/>'s.
    /// </summary>
    public static StoredGroups Parse(string? text, IReadOnlyDictionary<long, string>? states = null)
    {
        if (string.IsNullOrEmpty(text))
        {
            return Paper;
        }

        var d = JsonSerializer.Deserialize(text, StoredGroupsJson.Default.DictionaryStringStringArray)
            ?? throw new InvalidDataException($"programs.groups: not a group list: {text}");
        return new StoredGroups(d.TryGetValue("G", out var g) ? g : [], d.TryGetValue("M", out var m) ? m : [], states);
    }

    /// <summary>
    /// The <c>group_states</c> text of a state: the values of the G groups after the ninth and the M groups after the
    /// third, <c>{"G":[94,null,98],"M":[6]}</c>; null when the profile has no more groups than the columns.
    /// </summary>
    public static string? MoreText(ModalState state)
    {
        if (state.G.Count <= GColumns && state.M.Count <= MColumns)
        {
            return null;
        }

        var sb = new StringBuilder(64).Append("{\"G\":[");
        Append(sb, state.G, GColumns);
        sb.Append("],\"M\":[");
        Append(sb, state.M, MColumns);
        return sb.Append("]}").ToString();
    }

    /// <summary>The state's group values from the columns (<paramref name="gColumn"/> 0..8, <paramref name="mColumn"/> 0..2) and its <c>group_state</c>.</summary>
    public (CodeValues G, CodeValues M) Values(Func<int, double?> gColumn, Func<int, double?> mColumn, long? state)
    {
        double?[]? gMore = null;
        double?[]? mMore = null;
        if (state is { } id)
        {
            var more = _states.TryGetValue(id, out var text) ? text : throw new InvalidDataException($"group state {id} is not stored");
            using var doc = JsonDocument.Parse(more);
            gMore = Numbers(doc.RootElement, "G");
            mMore = Numbers(doc.RootElement, "M");
        }

        return (Build(GNames.Count, GColumns, gColumn, gMore), Build(MNames.Count, MColumns, mColumn, mMore));
    }

    private static CodeValues Build(int count, int columns, Func<int, double?> column, double?[]? more)
    {
        var values = new double?[count];
        for (var i = 0; i < count; i++)
        {
            values[i] = i < columns ? column(i) : more is { } m && i - columns < m.Length ? m[i - columns] : null;
        }

        return new CodeValues(values);
    }

    private static double?[]? Numbers(JsonElement root, string name) =>
        root.TryGetProperty(name, out var a)
            ? a.EnumerateArray().Select(e => e.ValueKind == JsonValueKind.Null ? (double?)null : e.GetDouble()).ToArray()
            : null;

    private static void Append(StringBuilder sb, CodeValues values, int from)
    {
        for (var i = from; i < values.Count; i++)
        {
            if (i > from)
            {
                sb.Append(',');
            }

            sb.Append(values[i] is { } v ? v.ToString("R", CultureInfo.InvariantCulture) : "null");
        }
    }
}

/// <summary>Source-generated JSON for the group lists (no reflection: the CLI is published with Native AOT).</summary>
[System.Text.Json.Serialization.JsonSerializable(typeof(Dictionary<string, string[]>))]
internal sealed partial class StoredGroupsJson : System.Text.Json.Serialization.JsonSerializerContext;
