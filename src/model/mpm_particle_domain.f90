!> The current size of a particle's domain, from its deformation gradient and its initial
!> half-sizes (cpGIMP). The half-sizes are not kept with the particles: the stencils take
!> those of a block of particles at once (`domain_half_sizes_block`, a loop across them that
!> vectorises), the contact gaps those of one particle (`domain_half_sizes`).
module mpm_particle_domain
    use mpm_kinds, only: wp
    implicit none
    private
    public :: domain_half_sizes, domain_half_sizes_block

contains

    !> Half-sizes of a particle's cpGIMP domain from its deformation gradient: along axis a,
    !> lp_a = sqrt(sum_b (F_ab lp0_b)^2), the root-mean-square extent along x_a of the
    !> deformed reference box (edges F e_b lp0_b). A stretch along the axes gives lp0_a F_aa,
    !> as lp0_a |F_aa| does, but a rotation leaves the size unchanged: lp0_a |F_aa| shrank
    !> the domain of a particle turned by 90 degrees to a point (linear hat weights), and the
    !> free end of a hanging cantilever turned unstable there (docs/accuracy-vs-cost.md).
    pure subroutine domain_half_sizes(f, lp0, dim, lp)
        integer, intent(in) :: dim
            !! space dimensions (2 or 3)
        real(wp), intent(in) :: f(dim, dim)
            !! deformation gradient
        real(wp), intent(in) :: lp0(dim)
            !! half-sizes of the reference domain [m]
        real(wp), intent(out) :: lp(dim)
            !! half-sizes of the current domain [m]

        call domain_half_sizes_block(dim, 1, f, lp0, lp)
    end subroutine domain_half_sizes

    !> domain_half_sizes of n particles, in a loop across them that vectorises.
    pure subroutine domain_half_sizes_block(dim, n, f, lp0, lp)
        integer, intent(in) :: dim
            !! space dimensions (2 or 3)
        integer, intent(in) :: n
            !! particles
        real(wp), intent(in) :: f(dim, dim, n)
            !! deformation gradients
        real(wp), intent(in) :: lp0(dim, n)
            !! half-sizes of the reference domains [m]
        real(wp), intent(out) :: lp(dim, n)
            !! half-sizes of the current domains [m]
        integer :: a, p

        ! the plain root of the sum of squares, not norm2: norm2 rescales element by element
        ! against overflow (a division and a branch each), which only half-sizes beyond
        ! 1e150 m would need
        if (dim == 2) then
            do p = 1, n
                lp(1, p) = sqrt((f(1, 1, p)*lp0(1, p))**2 + (f(1, 2, p)*lp0(2, p))**2)
                lp(2, p) = sqrt((f(2, 1, p)*lp0(1, p))**2 + (f(2, 2, p)*lp0(2, p))**2)
            end do
        else
            do p = 1, n
                do a = 1, 3
                    lp(a, p) = sqrt((f(a, 1, p)*lp0(1, p))**2 + (f(a, 2, p)*lp0(2, p))**2 &
                        + (f(a, 3, p)*lp0(3, p))**2)
                end do
            end do
        end if
    end subroutine domain_half_sizes_block

end module mpm_particle_domain
