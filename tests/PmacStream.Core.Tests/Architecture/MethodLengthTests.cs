using System.Text.RegularExpressions;
using Microsoft.CodeAnalysis;
using Microsoft.CodeAnalysis.CSharp;
using Microsoft.CodeAnalysis.CSharp.Syntax;

namespace PmacStream.Core.Tests.Architecture;

/// <summary>
/// No method in src/ runs over <see cref="Limit"/> lines, except the measured hot loops kept whole on purpose and the
/// listed ones still to split. Lines are counted as issue 24 counts them: from the declaration's first line
/// (after its attributes) to its closing brace, lambdas and local functions included.
/// </summary>
public sealed class MethodLengthTests
{
    /// <summary>The longest a method may be.</summary>
    public const int Limit = 80;

    /// <summary>
    /// The methods allowed over the limit, each with why: a hot loop names the benchmark that shows splitting it would
    /// cost; a method still to split says so, and its entry goes when it is split (the list only shrinks).
    /// </summary>
    public static readonly IReadOnlyDictionary<string, string> Allowed = new Dictionary<string, string>
    {
        // Measured hot loops, kept whole: one call per line or per statement, where a split adds calls and state passing.
        ["Interpreter.StepBlock"] = "hot loop: every block of check and split; bench/PmacStream.Benchmarks/GCode/CheckBenchmarks.cs \"check + interpret records 100k lines\", bench/scripts/split-bench.sh",
        ["Interpreter.TakeValues"] = "hot loop: every motion block; bench/PmacStream.Benchmarks/GCode/CheckBenchmarks.cs \"check + interpret records 100k lines\"",
        ["LineLexer.Lex"] = "hot loop: every character of every program; bench/PmacStream.Benchmarks/GCode/CheckBenchmarks.cs \"lex 100k lines\"",
        ["CheckRun.Line"] = "hot loop: every line checked; bench/PmacStream.Benchmarks/GCode/CheckBenchmarks.cs \"check 100k lines\", bench/scripts/check-bench.sh",
        ["Lexer.Tokenize"] = "hot loop: every command line the simulator receives; bench/PmacStream.Benchmarks/Sim/SimulatorBenchmarks.cs DownloadLines",
        ["CoordinateSystem.Execute"] = "hot loop: every program statement the simulator runs; bench/PmacStream.Benchmarks/Sim/SimulatorBenchmarks.cs ExecuteInstant (h28-stream is changing the simulator's timing in this file)",
        ["OnlineCommands.ExecuteOnline"] = "hot loop: every online command the simulator receives; bench/PmacStream.Benchmarks/Sim/SimulatorBenchmarks.cs DownloadLines (h25-sim is adding jog/home/status commands here)",
        ["ProgramLineSource.Scan"] = "hot loop: every byte of the opened program; bench/PmacStream.Benchmarks/Hmi/OpenLargeProgramBenchmark.cs WholeIndex",

        ["Splitter.SourceReader.Read"] = "hot loop: the splitter's reading thread, every line (the axis lane on the read buffer first); bench/scripts/split-bench.sh",
        ["Splitter.ChunkLineWriter.Write"] = "hot loop: the splitter's writing thread, every line into its chunk; bench/scripts/split-bench.sh",
        ["MacroExpander.Execute"] = "hot loop: every line of an expanded program; bench/PmacStream.Benchmarks/GCode/MacroExpansionBench.cs (macro-expand)",
        ["Interpreter.CheckDialect"] = "hot loop: every block checked, allocation-free unless it warns; bench/PmacStream.Benchmarks/GCode/CheckBenchmarks.cs \"check 100k lines\"",
    };

    [Fact]
    public void No_method_outside_the_allow_list_is_over_the_limit()
    {
        var over = LongMethods().Where(m => !Allowed.ContainsKey(m.Name)).Select(m => $"{m.Name} ({m.Lines} lines, {m.File})");
        over.Should().BeEmpty($"a method over {Limit} lines is split by concern, or (a measured hot loop) listed with its benchmark");
    }

    [Fact]
    public void Every_allow_list_entry_is_still_long()
    {
        var longNow = LongMethods().Select(m => m.Name).ToHashSet();
        Allowed.Keys.Where(k => !longNow.Contains(k)).Should().BeEmpty("an entry whose method is split (or gone) leaves the list");
    }

    [Fact]
    public void Every_hot_loop_names_a_benchmark_that_exists()
    {
        foreach (var (name, why) in Allowed.Where(e => !e.Value.StartsWith("to split: ", StringComparison.Ordinal)))
        {
            var benchmarks = Regex.Matches(why, @"bench/[\w./-]+").Select(m => m.Value).ToList();
            benchmarks.Should().NotBeEmpty($"{name} is kept whole as a hot loop: its entry names the benchmark that measures it");
            benchmarks.Where(b => !File.Exists(Path.Combine(RepoRoot.Path, b))).Should().BeEmpty($"{name}'s benchmark is in bench/");
        }
    }

    [Fact]
    public void The_count_matches_the_issue_on_a_known_shape()
    {
        const string source = """
            namespace N;
            class C
            {
                [System.Obsolete]
                public void M()
                {
                    var f = () =>
                    {
                        return 1;
                    };
                }

                public C() { }

                public int P
                {
                    get
                    {
                        return 1;
                    }
                }
            }
            """;
        Measure(CSharpSyntaxTree.ParseText(source), "x.cs").Select(m => (m.Name, m.Lines)).Should().Equal(
            [("C.M", 7), ("C..ctor", 1), ("C.P.get", 4)]);
    }

    /// <summary>A method's name as the allow-list writes it, its length in lines, and the file it is in.</summary>
    public sealed record Method(string Name, int Lines, string File);

    /// <summary>Every method, constructor, operator and accessor under src/ over the limit.</summary>
    public static IReadOnlyList<Method> LongMethods()
    {
        var src = Path.Combine(RepoRoot.Path, "src");
        return Directory.EnumerateFiles(src, "*.cs", SearchOption.AllDirectories)
            .Where(f => !IsBuildOutput(Path.GetRelativePath(src, f)))
            .SelectMany(f => Measure(CSharpSyntaxTree.ParseText(File.ReadAllText(f), path: f), Path.GetRelativePath(RepoRoot.Path, f)))
            .Where(m => m.Lines > Limit)
            .OrderByDescending(m => m.Lines)
            .ToList();
    }

    private static bool IsBuildOutput(string relative) =>
        relative.Split(Path.DirectorySeparatorChar, Path.AltDirectorySeparatorChar) is var parts
        && parts.Any(p => p is "bin" or "obj");

    private static IEnumerable<Method> Measure(SyntaxTree tree, string file)
    {
        foreach (var node in tree.GetRoot().DescendantNodes())
        {
            var (name, attributes) = node switch
            {
                MethodDeclarationSyntax m => (m.Identifier.Text, m.AttributeLists),
                ConstructorDeclarationSyntax c => (c.Modifiers.Any(SyntaxKind.StaticKeyword) ? ".cctor" : ".ctor", c.AttributeLists),
                DestructorDeclarationSyntax d => ("Finalize", d.AttributeLists),
                OperatorDeclarationSyntax o => ("op_" + o.OperatorToken.Text, o.AttributeLists),
                ConversionOperatorDeclarationSyntax c => ("op_" + c.Type, c.AttributeLists),
                AccessorDeclarationSyntax a => (Owner(a) + "." + a.Keyword.Text, a.AttributeLists),
                _ => (null, default(SyntaxList<AttributeListSyntax>)),
            };
            if (name is null)
            {
                continue;
            }

            var first = attributes.Count > 0 ? attributes[^1].GetLastToken().GetNextToken() : node.GetFirstToken();
            var lines = tree.GetLineSpan(node.Span).EndLinePosition.Line - first.GetLocation().GetLineSpan().StartLinePosition.Line + 1;
            yield return new Method(TypeName(node) + "." + name, lines, file);
        }
    }

    private static string Owner(AccessorDeclarationSyntax accessor) => accessor.Parent?.Parent switch
    {
        PropertyDeclarationSyntax p => p.Identifier.Text,
        EventDeclarationSyntax e => e.Identifier.Text,
        IndexerDeclarationSyntax => "this[]",
        _ => "?",
    };

    private static string TypeName(SyntaxNode node) =>
        string.Join(".", node.Ancestors().OfType<BaseTypeDeclarationSyntax>().Reverse().Select(t => t.Identifier.Text));
}
