using System.Collections;

namespace PmacStream.GCode;

/// <summary>
/// The code in force in each modal group of a profile (null: none, or a non-modal group on another block), in the
/// profile's group order. Immutable and compared by value, so states read back from the store equal the
/// interpreter's.
/// </summary>
public sealed class CodeValues : IReadOnlyList<double?>, IEquatable<CodeValues>
{
    private readonly double?[] _values;

    /// <summary>Takes a copy of the values.</summary>
    public CodeValues(IEnumerable<double?> values) => _values = values.ToArray();

    private CodeValues(double?[] values, bool owned) => _values = owned ? values : (double?[])values.Clone();

    /// <summary>No groups.</summary>
    public static CodeValues Empty { get; } = new([], owned: true);

    /// <inheritdoc />
    public int Count => _values.Length;

    /// <inheritdoc />
    public double? this[int index] => _values[index];

    /// <summary>The value of a group, or null when the profile has fewer groups.</summary>
    public double? At(int index) => (uint)index < (uint)_values.Length ? _values[index] : null;

    /// <summary>True when some group holds exactly this code number.</summary>
    public bool Holds(double code)
    {
        foreach (var v in _values)
        {
            if (v == code)
            {
                return true;
            }
        }

        return false;
    }

    /// <summary>The first value that satisfies <paramref name="match"/>, or null.</summary>
    public double? FirstWhere(Func<double, bool> match)
    {
        foreach (var v in _values)
        {
            if (v is { } x && match(x))
            {
                return x;
            }
        }

        return null;
    }

    /// <summary>A copy of an array the caller keeps changing.</summary>
    internal static CodeValues CopyOf(double?[] values) => values.Length == 0 ? Empty : new(values, owned: false);

    /// <inheritdoc />
    public bool Equals(CodeValues? other) => other is not null && _values.AsSpan().SequenceEqual(other._values);

    /// <inheritdoc />
    public override bool Equals(object? obj) => Equals(obj as CodeValues);

    /// <inheritdoc />
    public override int GetHashCode()
    {
        var h = new HashCode();
        foreach (var v in _values)
        {
            h.Add(v);
        }

        return h.ToHashCode();
    }

    /// <inheritdoc />
    public IEnumerator<double?> GetEnumerator() => ((IEnumerable<double?>)_values).GetEnumerator();

    IEnumerator IEnumerable.GetEnumerator() => GetEnumerator();

    /// <summary>The values as G-code numbers, <c>-</c> for none: <c>1 21 90 -</c>.</summary>
    public override string ToString() => string.Join(' ', _values.Select(v => v is { } x ? ModalState.Num(x) : "-"));
}
