using PmacStream.Plc;

namespace PmacStream.Testing;

/// <summary>
/// The PLC programs of the test programs family: a ladder under <c>samples/plc</c>, parsed and generated into the
/// Turbo PMAC PLC the rigs download and scan.
/// </summary>
public static class PlcSamples
{
    /// <summary>The sample ladder file <paramref name="file"/>.</summary>
    public static string Path_(string file) => RepoRoot.Sample("plc", file);

    /// <summary>The ladder <paramref name="file"/> parsed, and the PLC generated from it.</summary>
    public static (LadderProgram Program, GeneratedPlc Generated) Load(string file)
    {
        var program = LadderParser.Parse(File.ReadAllText(Path_(file)), file);
        return (program, PlcGenerator.Generate(program));
    }
}
