!> The terrain surface (mpm_terrain): nearest points on a triangle, signed distances and
!> normals through the cell index, independence of the triangulation (a tilted plane of 2 or
!> 2 000 triangles), the orientation against gravity, the 2D section, the refusal of a
!> surface that misses the domain, and the pruned query of the index against every triangle.
program test_mpm_terrain
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_error, only: error_type, exit_input
    use mpm_strings, only: int_text
    use mpm_terrain, only: terrain_type, new_terrain, terrain_distance, &
        closest_point_on_triangle
    implicit none

    type(test_suite_type) :: suite
    real(wp), parameter :: pi = acos(-1.0_wp), theta = pi/6, g(3) = [0.0_wp, 0.0_wp, -9.81_wp]

    call new_suite(suite, "mpm_terrain")
    call test_closest_point()
    call test_triangulation()
    call test_orientation()
    call test_ridge_tie()
    call test_section_2d()
    call test_misses_domain()
    call test_against_all_triangles()
    call finish(suite)

contains

    subroutine test_closest_point()
        real(wp) :: a(3), b(3), c(3), q(3)

        a = [0.0_wp, 0.0_wp, 0.0_wp]
        b = [1.0_wp, 0.0_wp, 0.0_wp]
        c = [0.0_wp, 1.0_wp, 0.0_wp]
        q = closest_point_on_triangle([0.25_wp, 0.25_wp, 2.0_wp], a, b, c)
        call check(suite, all(abs(q - [0.25_wp, 0.25_wp, 0.0_wp]) < 1e-15_wp), "face interior")
        q = closest_point_on_triangle([0.5_wp, -1.0_wp, 0.5_wp], a, b, c)
        call check(suite, all(abs(q - [0.5_wp, 0.0_wp, 0.0_wp]) < 1e-15_wp), "edge ab")
        q = closest_point_on_triangle([1.0_wp, 1.0_wp, 0.0_wp], a, b, c)
        call check(suite, all(abs(q - [0.5_wp, 0.5_wp, 0.0_wp]) < 1e-15_wp), "edge bc")
        q = closest_point_on_triangle([-1.0_wp, -1.0_wp, 1.0_wp], a, b, c)
        call check(suite, all(q == a), "corner a")
        q = closest_point_on_triangle([2.0_wp, -0.5_wp, 0.0_wp], a, b, c)
        call check(suite, all(q == b), "corner b")
    end subroutine test_closest_point

    !> The plane z = tan(theta) x over [0, 1] x [0, 1] as m x m squares of 2 triangles.
    function tilted_plane(m) result(corner)
        integer, intent(in) :: m
        real(wp), allocatable :: corner(:, :, :)

        integer :: i, j, t
        real(wp) :: x0, x1, y0, y1

        allocate (corner(3, 3, 2*m*m))
        t = 0
        do j = 0, m - 1
            do i = 0, m - 1
                x0 = real(i, wp)/m
                x1 = real(i + 1, wp)/m
                y0 = real(j, wp)/m
                y1 = real(j + 1, wp)/m
                t = t + 1
                corner(:, :, t) = reshape([x0, y0, z(x0), x1, y0, z(x1), x1, y1, z(x1)], [3, 3])
                t = t + 1
                corner(:, :, t) = reshape([x0, y0, z(x0), x1, y1, z(x1), x0, y1, z(x0)], [3, 3])
            end do
        end do
    end function tilted_plane

    pure real(wp) function z(x)
        real(wp), intent(in) :: x
        z = tan(theta)*x
    end function z

    subroutine test_triangulation()
        type(terrain_type) :: coarse, fine
        type(error_type), allocatable :: error
        real(wp) :: x(3), d1, d2, n1(3), n2(3), exact
        logical :: f1, f2
        integer :: k

        call new_terrain(coarse, tilted_plane(1), [0.0_wp, 0.0_wp, -0.5_wp], [10, 10, 15], &
            0.1_wp, 3, 0.2_wp, g, error)
        call check(suite, .not. allocated(error), "plane of 2 triangles indexed")
        call new_terrain(fine, tilted_plane(32), [0.0_wp, 0.0_wp, -0.5_wp], [10, 10, 15], &
            0.1_wp, 3, 0.2_wp, g, error)
        call check(suite, .not. allocated(error), "plane of 2048 triangles indexed")
        call check(suite, coarse%n == 2 .and. fine%n == 2048, "triangle counts")
        do k = 1, 40
            ! points above and below the plane, inside its extent
            x = [0.1_wp + 0.02_wp*k, 0.9_wp - 0.015_wp*k, 0.0_wp]
            x(3) = z(x(1)) + 0.15_wp*cos(real(k, wp))
            call terrain_distance(coarse, x, f1, d1, n1)
            call terrain_distance(fine, x, f2, d2, n2)
            exact = (x(3) - z(x(1)))*cos(theta)
            call check(suite, f1 .and. f2, "points within reach are found")
            call check_close(suite, d1, exact, 1e-12_wp, "signed distance, 2 triangles")
            call check_close(suite, d2, exact, 1e-12_wp, "signed distance, 2048 triangles")
            call check(suite, all(abs(n1 - [-sin(theta), 0.0_wp, cos(theta)]) < 1e-12_wp) .and. &
                all(abs(n2 - n1) < 1e-12_wp), "normal up the slope, the same for both")
        end do
        call terrain_distance(coarse, [0.5_wp, 0.5_wp, 0.8_wp], f1, d1, n1)
        call check(suite, .not. f1, "a point beyond reach is not found")
    end subroutine test_triangulation

    subroutine test_orientation()
        type(terrain_type) :: terrain
        type(error_type), allocatable :: error
        real(wp), allocatable :: corner(:, :, :)
        real(wp) :: d, n(3)
        logical :: found

        ! the same plane with every triangle listed the other way round: normals down
        corner = tilted_plane(2)
        corner(:, 2:3, :) = corner(:, 3:2:-1, :)
        call new_terrain(terrain, corner, [0.0_wp, 0.0_wp, -0.5_wp], [10, 10, 15], 0.1_wp, 3, &
            0.2_wp, g, error)
        call terrain_distance(terrain, [0.5_wp, 0.5_wp, z(0.5_wp) + 0.1_wp], found, d, n)
        call check(suite, found .and. d > 0.0_wp .and. n(3) > 0.0_wp, &
            "normals turned against gravity: above the plane is the material side")
    end subroutine test_orientation

    !> A point straight above the crest of a symmetric ridge is as far from both slopes: the
    !> answer is the triangle listed first in the surface (the lower index), in whatever order
    !> the index lists them, and the query skips no triangle that could be as near.
    subroutine test_ridge_tie()
        type(terrain_type) :: ridge, swapped
        type(error_type), allocatable :: error
        real(wp) :: corner(3, 3, 2), d1, d2, n1(3), n2(3), x(3)
        logical :: f1, f2

        ! the slopes x in [0.2, 0.5] rising and [0.5, 0.8] falling, crest along y at x = 0.5
        corner(:, :, 1) = reshape([0.2_wp, -1.0_wp, 0.4_wp, 0.5_wp, -1.0_wp, 0.55_wp, &
            0.5_wp, 2.0_wp, 0.55_wp], [3, 3])
        corner(:, :, 2) = reshape([0.5_wp, -1.0_wp, 0.55_wp, 0.8_wp, -1.0_wp, 0.4_wp, &
            0.5_wp, 2.0_wp, 0.55_wp], [3, 3])
        call new_terrain(ridge, corner, [0.0_wp, 0.0_wp, 0.0_wp], [10, 10, 10], 0.1_wp, 3, &
            0.2_wp, g, error)
        call check(suite, .not. allocated(error), "ridge indexed")
        call new_terrain(swapped, corner(:, :, [2, 1]), [0.0_wp, 0.0_wp, 0.0_wp], [10, 10, 10], &
            0.1_wp, 3, 0.2_wp, g, error)
        x = [0.5_wp, 0.55_wp, 0.6_wp]
        call terrain_distance(ridge, x, f1, d1, n1)
        call terrain_distance(swapped, x, f2, d2, n2)
        call check(suite, f1 .and. f2, "the crest is within reach")
        call check_close(suite, d1, 0.05_wp, 1e-12_wp, "distance to the crest")
        call check(suite, d1 == d2, "the same distance from either surface")
        call check(suite, n1(1) < 0.0_wp, "a tie goes to triangle 1 (the rising slope)")
        call check(suite, n2(1) > 0.0_wp, "listed the other way, to the falling slope")
    end subroutine test_ridge_tie

    subroutine test_section_2d()
        type(terrain_type) :: terrain
        type(error_type), allocatable :: error
        real(wp), allocatable :: corner(:, :, :)
        real(wp) :: d, n(3)
        logical :: found

        ! the plane y = tan(theta) x, extruded along z across z = 0, for a 2D case (x, y)
        corner = tilted_plane(3)
        corner([1, 2, 3], :, :) = corner([1, 3, 2], :, :)
        corner(3, :, :) = corner(3, :, :) - 0.5_wp
        call new_terrain(terrain, corner, [0.0_wp, -0.5_wp, 0.0_wp], [10, 15, 1], 0.1_wp, 2, &
            0.2_wp, [0.0_wp, -9.81_wp, 0.0_wp], error)
        call check(suite, .not. allocated(error), "2D section indexed")
        call terrain_distance(terrain, [0.4_wp, z(0.4_wp) + 0.05_wp, 0.0_wp], found, d, n)
        call check(suite, found, "2D point found")
        call check_close(suite, d, 0.05_wp*cos(theta), 1e-12_wp, "2D signed distance")
        call check(suite, n(2) > 0.0_wp .and. abs(n(3)) < 1e-12_wp, "2D normal in the plane, up")
    end subroutine test_section_2d

    subroutine test_misses_domain()
        type(terrain_type) :: terrain
        type(error_type), allocatable :: error
        real(wp), allocatable :: corner(:, :, :)

        corner = tilted_plane(1)
        corner(3, :, :) = corner(3, :, :) + 100.0_wp
        call new_terrain(terrain, corner, [0.0_wp, 0.0_wp, -0.5_wp], [10, 10, 15], 0.1_wp, 3, &
            0.2_wp, g, error)
        call check(suite, allocated(error), "a surface far above the domain is refused")
        if (allocated(error)) call check(suite, error%code == exit_input .and. &
            index(error%message, "does not come within reach of the domain") > 0, &
            "refusal: input error that says why")
    end subroutine test_misses_domain

    !> The index query skips triangles by bounds (the list order, the plane and circle of
    !> each triangle): on a bumpy surface, 4 000 points above, below and beside it find what
    !> a search of every triangle finds (the same bits; ties to the lowest index).
    subroutine test_against_all_triangles()
        integer, parameter :: m = 24
        type(terrain_type) :: terrain
        type(error_type), allocatable :: error
        real(wp), allocatable :: corner(:, :, :)
        real(wp) :: x(3), d, n(3), q(3), dist, best, d_all, n_all(3), reach
        integer :: i, j, t, k, nearest, wrong, found_count
        logical :: found

        allocate (corner(3, 3, 2*m*m))
        t = 0
        do j = 0, m - 1
            do i = 0, m - 1
                t = t + 1
                corner(:, :, t) = reshape([bump(i, j, m), bump(i + 1, j, m), &
                    bump(i + 1, j + 1, m)], [3, 3])
                t = t + 1
                corner(:, :, t) = reshape([bump(i, j, m), bump(i + 1, j + 1, m), &
                    bump(i, j + 1, m)], [3, 3])
            end do
        end do
        reach = 0.2_wp
        call new_terrain(terrain, corner, [0.0_wp, 0.0_wp, 0.0_wp], [10, 10, 10], 0.1_wp, 3, &
            reach, g, error)
        call check(suite, .not. allocated(error), "bumpy surface indexed")
        if (allocated(error)) return
        wrong = 0
        found_count = 0
        do k = 1, 4000
            ! a quasi-random point in the box (golden-ratio sequences)
            x = [modulo(0.6180339887_wp*k, 1.0_wp), modulo(0.7548776662_wp*k, 1.0_wp), &
                modulo(0.5698402910_wp*k, 1.0_wp)]
            call terrain_distance(terrain, x, found, d, n)
            best = huge(1.0_wp)
            nearest = 0
            do t = 1, terrain%n
                q = closest_point_on_triangle(x, terrain%corner(:, 1, t), &
                    terrain%corner(:, 2, t), terrain%corner(:, 3, t))
                dist = norm2(x - q)
                if (dist < best) then
                    best = dist
                    nearest = t
                    n_all = terrain%normal(:, t)
                    d_all = sign(dist, dot_product(x - q, n_all))
                end if
            end do
            if (found .neqv. best <= reach) then
                wrong = wrong + 1
            else if (found) then
                found_count = found_count + 1
                if (d /= d_all .or. any(n /= n_all)) wrong = wrong + 1
            end if
        end do
        call check(suite, wrong == 0, "indexed queries = search of every triangle ("// &
            "points within reach: "//int_text(found_count)//")")
        call check(suite, found_count > 1000, "many of the points are within reach")


    end subroutine test_against_all_triangles

    !> Corner (i, j) of an m x m raster: z = 0.5 + 0.1 sin(7x) cos(5y) over [0, 1]^2.
    pure function bump(i, j, m) result(c)
        integer, intent(in) :: i, j, m
        real(wp) :: c(3)
        c(1) = real(i, wp)/m
        c(2) = real(j, wp)/m
        c(3) = 0.5_wp + 0.1_wp*sin(7.0_wp*c(1))*cos(5.0_wp*c(2))
    end function bump

end program test_mpm_terrain
